#pragma once
/// @file solver_comparison.hpp
/// Side-by-side timing of the solvers of eq. (7) (Chentanez et al. 2006) on the very system a
/// coupled step solved: the speed figures of the scaling report (`coupling.compare_solvers`).
///
/// After the step's own solve, each named solver solves the same system again from the same
/// initial guess (the previous step's pressure and the current solid velocities) to the same
/// tolerance; its time and iterations are recorded and its answer discarded, so the run is the
/// run without the comparison. Names:
///  - `bicgstab`, `umfpack`: eq. (7) by that solver (coupled_solver.hpp), fresh every step;
///  - `projection`: the fluid block alone, P p = r with P = (h/ρ) GᵀVG on the same unknowns, by the
///    fluid's own pressure solver (fluid.solver: BoomerAMG-CG by default) with its set-up included:
///    the fluid-only projection of this mesh, the solids held as walls (Ando et al. 2013, sec. 3).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "coupling/coupled_system.hpp"
#include "coupling/solvers/coupled_solver.hpp"
#include "fluid/projection/linear_solver.hpp"

namespace tetfsi::coupling {

/// One comparison solve of one step.
struct ComparedSolve {
  std::string name;      ///< "bicgstab", "umfpack" or "projection"
  double seconds = 0;    ///< set-up + solve [s]
  int iterations = 0;    ///< 0 for the direct solver
  std::string failure;   ///< why the solver missed its tolerance ("" if it converged)
};

class SolverComparison {
 public:
  /// @param names           solvers to compare against the step's own (each at most once)
  /// @param coupled_options tolerance and iteration limit of eq. (7)'s solvers (the step's own)
  /// @param fluid_options   the fluid's pressure solver, for `projection`
  /// @throws std::invalid_argument on an unknown name
  SolverComparison(const std::vector<std::string>& names, const CoupledSolverOptions& coupled_options,
                   const fluid::SolverOptions& fluid_options);
  ~SolverComparison();

  /// Solves `system` with every compared solver from the guess (u0, p0). A solver that misses its
  /// tolerance is reported with its `failure` (and the time it took), not thrown: the run goes on.
  std::vector<ComparedSolve> run(const CoupledSystem& system, const Eigen::VectorXd& u0,
                                 const Eigen::VectorXd& p0) const;

  const std::vector<std::string>& names() const { return names_; }

 private:
  std::vector<std::string> names_;
  std::vector<std::unique_ptr<CoupledSolver>> solvers_;  ///< per name; null for `projection`
  fluid::SolverOptions fluid_options_;
};

}  // namespace tetfsi::coupling
