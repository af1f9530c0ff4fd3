#include "parallel/mpi_session.hpp"

// Only the C API of MPI is used: keep Open MPI's C++ bindings (libmpi_cxx) out of the link.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#include <omp.h>
#include <petscsys.h>

#include <cstdlib>

namespace tetfsi::parallel {
namespace {

bool mpi_running() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  return initialized && !finalized;
}

void finalize_mpi() {
  if (mpi_running()) MPI_Finalize();
}

void finalize_petsc() {
  PetscBool done = PETSC_FALSE;
  PetscFinalized(&done);
  if (!done) PetscFinalize();
}

}  // namespace

void initialize_mpi() {
  static const bool ready = [] {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
      MPI_Init(nullptr, nullptr);
      std::atexit(finalize_mpi);
    }
    return true;
  }();
  (void)ready;
}

void initialize_petsc() {
  static const bool ready = [] {
    initialize_mpi();
    // PETSc takes its options from these arguments and from $PETSC_OPTIONS (users may tune the
    // solver there); it must not install its signal handler (tetfsi reports its own errors) nor
    // print error traces (the calls' codes are turned into exceptions).
    static char program[] = "tetfsi", no_signal_handler[] = "-no_signal_handler";
    static char* arguments[] = {program, no_signal_handler, nullptr};
    int argc = 2;
    char** argv = arguments;
    PetscInitialize(&argc, &argv, nullptr, nullptr);
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    std::atexit(finalize_petsc);  // registered after MPI's: runs before it
    return true;
  }();
  (void)ready;
}

int rank() {
  if (!mpi_running()) return 0;
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int num_processes() {
  if (!mpi_running()) return 1;
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

void set_library_threads(int threads) { omp_set_num_threads(threads > 0 ? threads : 1); }

RowRange owned_rows(int n, int rank, int processes) {
  const int base = n / processes, extra = n % processes;
  RowRange r;
  r.begin = rank * base + (rank < extra ? rank : extra);
  r.end = r.begin + base + (rank < extra ? 1 : 0);
  return r;
}

void abort_all_if_parallel(int exit_code) {
  if (num_processes() > 1) MPI_Abort(MPI_COMM_WORLD, exit_code);
}

}  // namespace tetfsi::parallel
