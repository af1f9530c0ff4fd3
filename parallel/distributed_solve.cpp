#include "parallel/distributed_solve.hpp"

#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <petscksp.h>

#include <string>
#include <type_traits>
#include <vector>

#include "parallel/mpi_session.hpp"
#include "support/stopwatch.hpp"
#include "support/number_text.hpp"

namespace tetfsi::parallel {
namespace {

static_assert(std::is_same_v<PetscInt, int>, "Eigen's int indices are handed to PETSc as they are");
static_assert(std::is_same_v<PetscScalar, double>, "PETSc must be the real double-precision build");

void check(PetscErrorCode code, const char* call) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw PetscError(std::string("PETSc: ") + call + " failed: " + (text ? text : "error " + std::to_string(code)));
}
#define TETFSI_PETSC(call) check((call), #call)

/// The BoomerAMG settings of the file doc, under the options prefix `tetfsi_`, where the user has
/// not set them ($PETSC_OPTIONS).
void set_boomeramg_defaults() {
  static const char* const defaults[][2] = {
      {"-tetfsi_pc_hypre_boomeramg_coarsen_type", "HMIS"},
      {"-tetfsi_pc_hypre_boomeramg_interp_type", "ext+i"},
      {"-tetfsi_pc_hypre_boomeramg_P_max", "4"},
      {"-tetfsi_pc_hypre_boomeramg_strong_threshold", "0.5"},
      {"-tetfsi_pc_hypre_boomeramg_agg_nl", "1"},
      {"-tetfsi_pc_hypre_boomeramg_relax_type_down", "SOR/Jacobi"},
      {"-tetfsi_pc_hypre_boomeramg_relax_type_up", "backward-SOR/Jacobi"},
      {"-tetfsi_pc_hypre_boomeramg_relax_type_coarse", "Gaussian-elimination"},
      {"-tetfsi_pc_hypre_boomeramg_grid_sweeps_all", "1"},
      {"-tetfsi_pc_hypre_boomeramg_max_iter", "1"},
      {"-tetfsi_pc_hypre_boomeramg_tol", "0"},
      {"-tetfsi_pc_hypre_boomeramg_no_CF", "true"},  // lexicographic smoothing, hypre's default order
  };
  for (const auto& [key, value] : defaults) {
    PetscBool given = PETSC_FALSE;
    TETFSI_PETSC(PetscOptionsHasName(nullptr, nullptr, key, &given));
    if (!given) TETFSI_PETSC(PetscOptionsSetValue(nullptr, key, value));
  }
}

void configure_boomeramg(PC pc) {
  set_boomeramg_defaults();
  TETFSI_PETSC(PCSetType(pc, PCHYPRE));
  TETFSI_PETSC(PCHYPRESetType(pc, "boomeramg"));
}

/// The rows this process owns of a symmetric Eigen matrix (compressed column i = row i) as a
/// PETSc AIJ matrix over every process, preallocated exactly.
struct DistributedMatrix {
  explicit DistributedMatrix(const Eigen::SparseMatrix<double>& a) : n(static_cast<int>(a.rows())) {
    initialize_petsc();
    rows = owned_rows(n, rank(), num_processes());
    const int* start = a.outerIndexPtr();
    const int* column = a.innerIndexPtr();
    std::vector<PetscInt> diagonal_block(rows.size(), 0), off_block(rows.size(), 0);
    for (int i = rows.begin; i < rows.end; ++i)
      for (int k = start[i]; k < start[i + 1]; ++k)
        ++(column[k] >= rows.begin && column[k] < rows.end ? diagonal_block : off_block)[i - rows.begin];
    TETFSI_PETSC(MatCreateAIJ(PETSC_COMM_WORLD, rows.size(), rows.size(), n, n, 0, diagonal_block.data(), 0,
                              off_block.data(), &mat));
    for (int i = rows.begin; i < rows.end; ++i)
      TETFSI_PETSC(MatSetValues(mat, 1, &i, start[i + 1] - start[i], column + start[i], a.valuePtr() + start[i],
                                INSERT_VALUES));
    TETFSI_PETSC(MatAssemblyBegin(mat, MAT_FINAL_ASSEMBLY));
    TETFSI_PETSC(MatAssemblyEnd(mat, MAT_FINAL_ASSEMBLY));
  }
  ~DistributedMatrix() { MatDestroy(&mat); }
  DistributedMatrix(const DistributedMatrix&) = delete;
  DistributedMatrix& operator=(const DistributedMatrix&) = delete;

  int n = 0;
  RowRange rows;
  Mat mat = nullptr;
};

/// A vector distributed like DistributedMatrix's rows, and the gather of it back to every process.
struct DistributedVector {
  DistributedVector(const RowRange& owned, int n) : rows(owned) {
    TETFSI_PETSC(VecCreateMPI(PETSC_COMM_WORLD, rows.size(), n, &vec));
    TETFSI_PETSC(VecScatterCreateToAll(vec, &gather, &whole));
  }
  ~DistributedVector() {
    VecScatterDestroy(&gather);
    VecDestroy(&whole);
    VecDestroy(&vec);
  }
  DistributedVector(const DistributedVector&) = delete;
  DistributedVector& operator=(const DistributedVector&) = delete;

  /// This process's rows of the whole vector `values`.
  void set_owned(const Eigen::VectorXd& values) {
    PetscScalar* local = nullptr;
    TETFSI_PETSC(VecGetArray(vec, &local));
    for (int i = rows.begin; i < rows.end; ++i) local[i - rows.begin] = values[i];
    TETFSI_PETSC(VecRestoreArray(vec, &local));
  }
  /// The whole vector, gathered from every process.
  void get_whole(Eigen::VectorXd& values) {
    TETFSI_PETSC(VecScatterBegin(gather, vec, whole, INSERT_VALUES, SCATTER_FORWARD));
    TETFSI_PETSC(VecScatterEnd(gather, vec, whole, INSERT_VALUES, SCATTER_FORWARD));
    PetscInt size = 0;
    TETFSI_PETSC(VecGetSize(whole, &size));
    const PetscScalar* all = nullptr;
    TETFSI_PETSC(VecGetArrayRead(whole, &all));
    values = Eigen::Map<const Eigen::VectorXd>(all, size);
    TETFSI_PETSC(VecRestoreArrayRead(whole, &all));
  }

  RowRange rows;
  Vec vec = nullptr, whole = nullptr;
  VecScatter gather = nullptr;
};

}  // namespace

DistributedSolveReport solve_spd_distributed(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& b,
                                             Eigen::VectorXd& x, double tolerance, int max_iterations) {
  DistributedSolveReport report;
  Stopwatch clock;
  const DistributedMatrix matrix(a);
  DistributedVector rhs(matrix.rows, matrix.n), solution(matrix.rows, matrix.n);
  rhs.set_owned(b);
  solution.set_owned(x);

  KSP ksp = nullptr;
  struct Guard {
    KSP& k;
    ~Guard() { KSPDestroy(&k); }
  } guard{ksp};
  TETFSI_PETSC(KSPCreate(PETSC_COMM_WORLD, &ksp));
  TETFSI_PETSC(KSPSetOptionsPrefix(ksp, "tetfsi_"));
  TETFSI_PETSC(KSPSetOperators(ksp, matrix.mat, matrix.mat));
  TETFSI_PETSC(KSPSetType(ksp, KSPCG));
  TETFSI_PETSC(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED));
  TETFSI_PETSC(KSPSetTolerances(ksp, tolerance, PETSC_DEFAULT, PETSC_DEFAULT, max_iterations));
  TETFSI_PETSC(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE));
  PC pc = nullptr;
  TETFSI_PETSC(KSPGetPC(ksp, &pc));
  configure_boomeramg(pc);
  TETFSI_PETSC(KSPSetFromOptions(ksp));
  TETFSI_PETSC(KSPSetUp(ksp));
  report.setup_seconds = clock.lap();

  TETFSI_PETSC(KSPSolve(ksp, rhs.vec, solution.vec));
  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  TETFSI_PETSC(KSPGetConvergedReason(ksp, &reason));
  TETFSI_PETSC(KSPGetIterationNumber(ksp, &report.iterations));
  if (reason < 0)
    throw PetscError("PETSc CG with BoomerAMG did not converge (" + std::string(KSPConvergedReasons[reason]) + ") after " +
                     std::to_string(report.iterations) + " iterations (tolerance " + number_text(tolerance) + ")");
  solution.get_whole(x);
  report.solve_seconds = clock.lap();
  return report;
}

struct DistributedAmg::Impl {
  explicit Impl(const Eigen::SparseMatrix<double>& a) : matrix(a), r(matrix.rows, matrix.n), z(matrix.rows, matrix.n) {
    TETFSI_PETSC(PCCreate(PETSC_COMM_WORLD, &pc));
    TETFSI_PETSC(PCSetOptionsPrefix(pc, "tetfsi_"));
    TETFSI_PETSC(PCSetOperators(pc, matrix.mat, matrix.mat));
    configure_boomeramg(pc);
    TETFSI_PETSC(PCSetFromOptions(pc));
    TETFSI_PETSC(PCSetUp(pc));
  }
  ~Impl() { PCDestroy(&pc); }
  DistributedMatrix matrix;  // declared first: the vectors take its row ranges
  DistributedVector r, z;
  PC pc = nullptr;
};

DistributedAmg::DistributedAmg() = default;
DistributedAmg::~DistributedAmg() = default;
DistributedAmg::DistributedAmg(DistributedAmg&&) noexcept = default;
DistributedAmg& DistributedAmg::operator=(DistributedAmg&&) noexcept = default;

void DistributedAmg::setup(const Eigen::SparseMatrix<double>& a) {
  if (a.rows() < 1 || a.rows() != a.cols()) throw std::invalid_argument("DistributedAmg: square matrix of size >= 1 expected");
  impl_.reset();
  impl_ = std::make_unique<Impl>(a);
}

void DistributedAmg::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  if (!impl_) throw std::logic_error("DistributedAmg::apply before setup");
  impl_->r.set_owned(r);
  TETFSI_PETSC(PCApply(impl_->pc, impl_->r.vec, impl_->z.vec));
  impl_->z.get_whole(z);
}

}  // namespace tetfsi::parallel
