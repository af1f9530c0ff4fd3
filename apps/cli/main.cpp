/// @file main.cpp
/// The full `tetfsi` program (tetfsi-solver, started by the front program `tetfsi`, front.cpp):
/// every command. Exit codes in exit_codes.hpp. Under `mpirun -n N` every process runs the
/// command; the first prints, any error ends them all with its exit code.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>
#include <iostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "apps/cli/allocator.hpp"
#include "apps/cli/commands.hpp"
#include "apps/cli/exit_codes.hpp"
#include "apps/run/errors.hpp"
#include "apps/scene/scene.hpp"
#include "apps/version.hpp"
#include "parallel/mpi_session.hpp"

namespace {

/// An error of this process, printed, and with several MPI processes the whole run ended with
/// `code` at once (the others would otherwise wait for this one in their next distributed solve).
/// A scene, input or run error (`same_everywhere`) comes from checks every process makes alike on
/// the same state: the first process prints it and ends the run; the others wait for that, so it
/// is printed once.
int fail(int code, const std::string& message, bool same_everywhere) {
  const int processes = tetfsi::parallel::num_processes(), rank = tetfsi::parallel::rank();
  // Rank 0 aborts the run before this wait ends, unless it did not meet the error itself.
  if (processes > 1 && rank > 0 && same_everywhere) std::this_thread::sleep_for(std::chrono::seconds(30));
  if (processes > 1 && rank > 0) std::cerr << "[process " << rank << " of " << processes << "] ";
  std::cerr << message << std::flush;
  tetfsi::parallel::abort_all_if_parallel(code);
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace tetfsi;
  // Before anything allocates: undo a library's allocator settings (apps/cli/allocator.hpp).
  // Huge pages serve a run's per-step arrays; `validate` and `schema` allocate little, and
  // starting the program again would double their start-up (0.2 s of CPU: loading and binding its
  // 121 shared libraries, docs/reliability.md).
  const bool light = argc >= 2 && (std::strcmp(argv[1], "validate") == 0 || std::strcmp(argv[1], "schema") == 0);
  if (!light) cli::use_huge_pages_or_reexec(argv);
  cli::restore_large_block_mapping();
  std::string command_line;
  for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);
  return cli::with_exit_codes(
      [&] {
        // Under mpirun every process runs the same command (parallel/mpi_session.hpp); only the
        // first prints its results.
        if (parallel::launched_by_mpirun()) {
          parallel::initialize_mpi();
          if (parallel::rank() > 0 && !std::freopen("/dev/null", "w", stdout))
            throw std::runtime_error("cannot silence the standard output of an MPI process");
        }
        return cli::dispatch(argc, argv, command_line);
      },
      fail);
}
