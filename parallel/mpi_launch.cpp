// launched_by_mpirun (mpi_session.hpp), in a file of its own: it reads the environment only, so a
// program can ask it without linking MPI (apps/cli/front.cpp).
#include <cstdlib>
#include <initializer_list>

#include "parallel/mpi_session.hpp"

namespace tetfsi::parallel {

bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

}  // namespace tetfsi::parallel
