#pragma once
/// @file hypre_support.hpp
/// Private to fluid/projection: hypre objects behind RAII, shared by the BoomerAMG-PCG solve
/// (linear_solver.cpp) and the BoomerAMG preconditioner (amg_preconditioner.cpp). One MPI rank.
// Only the C API of MPI is used: keep Open MPI's C++ bindings (libmpi_cxx) out of the link.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <HYPRE.h>
#include <HYPRE_krylov.h>
#include <HYPRE_parcsr_ls.h>
#include <HYPRE_utilities.h>
#include <mpi.h>

#include <Eigen/SparseCore>
#include <vector>

namespace tetfsi::fluid::hypre {

/// Initialises MPI (if the caller has not) and hypre, once per process; MPI is finalised at exit.
void ensure_initialized();

/// A symmetric sparse matrix as a hypre ParCSR matrix (rows = Eigen's compressed columns).
class Matrix {
 public:
  explicit Matrix(const Eigen::SparseMatrix<double>& a);
  ~Matrix() { HYPRE_IJMatrixDestroy(ij_); }
  Matrix(const Matrix&) = delete;
  Matrix& operator=(const Matrix&) = delete;
  HYPRE_ParCSRMatrix par() const { return par_; }
  int size() const { return n_; }
  const std::vector<int>& rows() const { return rows_; }

 private:
  int n_ = 0;
  std::vector<int> rows_;
  HYPRE_IJMatrix ij_ = nullptr;
  HYPRE_ParCSRMatrix par_ = nullptr;
};

/// A vector of `rows.size()` entries as a hypre ParVector.
class Vector {
 public:
  Vector(const std::vector<int>& rows, const double* values);
  ~Vector() { HYPRE_IJVectorDestroy(ij_); }
  Vector(const Vector&) = delete;
  Vector& operator=(const Vector&) = delete;
  HYPRE_ParVector par() const { return par_; }
  void set(const double* values);
  void get(double* values) const;

 private:
  const std::vector<int>& rows_;
  HYPRE_IJVector ij_ = nullptr;
  HYPRE_ParVector par_ = nullptr;
};

/// BoomerAMG set to one V-cycle as a preconditioner: HMIS coarsening with extended+i
/// interpolation (strong threshold 0.5, for 3D Laplacians), one level of aggressive coarsening
/// (multipass interpolation) and symmetric hybrid Gauss-Seidel, so that the preconditioner is
/// symmetric and CG may use it.
HYPRE_Solver make_boomeramg_preconditioner();

}  // namespace tetfsi::fluid::hypre
