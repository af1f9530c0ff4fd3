#pragma once
/// @file linear_analysis.hpp
/// Small-displacement analyses of an ElasticModel about its rest state, with K0 = K'(0) and
/// the lumped mass M: linear statics K0 d = f and the lowest vibration mode K0 x = omega^2 M x
/// (inverse iteration). Used by the cantilever validation and the benchmark.
#include <Eigen/Core>
#include <vector>

#include "solid/elastic_model.hpp"

namespace tetfsi::solid {

/// Solves K0 d = f with d = 0 on the DOFs flagged in `fixed` (CHOLMOD).
/// @throws SolidError if K0 restricted to the free DOFs is not positive definite
///         (e.g. too few DOFs fixed to remove the rigid motions)
Eigen::VectorXd solve_linear_static(const ElasticModel& model, const std::vector<char>& fixed,
                                    const Eigen::VectorXd& f);

struct Mode {
  double omega = 0;        ///< angular frequency [rad/s]
  Eigen::VectorXd shape;   ///< 3n, M-normalized (x^T M x = 1), zero on fixed DOFs
  int iterations = 0;
};

/// Lowest mode reached by inverse iteration from `start` (choose a start in the wanted
/// mode's direction, e.g. a static deflection, when the lowest frequency is repeated).
/// Stops when the Rayleigh quotient changes by less than `tolerance` (relative).
Mode lowest_mode(const ElasticModel& model, const std::vector<char>& fixed, const Eigen::VectorXd& start,
                 double tolerance = 1e-12, int max_iterations = 200);

}  // namespace tetfsi::solid
