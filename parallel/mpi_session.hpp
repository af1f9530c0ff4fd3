#pragma once
/// @file mpi_session.hpp
/// The MPI processes of a run (`mpirun -n N tetfsi run SCENE`) and PETSc's life in them.
///
/// tetfsi distributes its linear solves, not its data: every process holds the whole mesh and
/// runs the whole step; the pressure projection and the coupled solve hand their matrix to PETSc
/// (distributed_solve.hpp), each process contributing the block of rows it owns, and every process
/// receives the whole solution back, so all processes stay on the same state. Only rank 0 writes
/// the output folder and prints.
///
/// MPI is initialised at the start of `tetfsi` when it was started by mpirun (launched_by_mpirun),
/// otherwise on the first solve that needs it (hypre, PETSc), and finalised at exit (PETSc first).
namespace tetfsi::parallel {

/// Whether this process was started by an MPI launcher (Open MPI's mpirun or a PMI/PMIx one),
/// from the environment the launcher sets. Safe before MPI is initialised.
bool launched_by_mpirun();

/// Initialises MPI once per process (no-op if already done), finalised at exit.
void initialize_mpi();

/// Initialises MPI and PETSc once per process (PETSc's own signal handler off, errors returned to
/// the caller instead of printed), PETSc finalised at exit before MPI.
void initialize_petsc();

/// This process's rank in MPI_COMM_WORLD and the number of processes; 0 and 1 while MPI is not
/// initialised (a run without mpirun).
int rank();
int num_processes();

/// Threads of the OpenMP regions inside the solver libraries (Debian's hypre is built with
/// OpenMP and would otherwise take every core in each process, however many processes share
/// them): the run's `simulation.threads`, like TBB's.
void set_library_threads(int threads);

/// Rows [begin, end) of an n-row matrix owned by `rank` of `processes`: contiguous blocks, the
/// first n mod processes blocks one row longer.
struct RowRange {
  int begin = 0, end = 0;
  int size() const { return end - begin; }
};
RowRange owned_rows(int n, int rank, int processes);

/// Ends every process of the run with `exit_code` (MPI_Abort when there are several: a process
/// that stops on an error must not leave the others waiting in a collective call); returns
/// normally with one process.
void abort_all_if_parallel(int exit_code);

}  // namespace tetfsi::parallel
