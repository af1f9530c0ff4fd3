/// @file front.cpp
/// The `tetfsi` program: runs `tetfsi validate` itself and starts the full program,
/// tetfsi-solver (main.cpp, in the same folder), for every other command, with the same
/// arguments, in the same process (execv: the process id, exit code and signals are the
/// solver's).
///
/// Why two programs: the solver links PETSc, hypre, Open MPI and OpenVDB, 121 shared libraries
/// whose loading and symbol binding (OpenVDB alone has 69k symbol relocations, bound at load)
/// take about 0.25 s of CPU before main(), and the solver then starts itself again to get huge
/// pages (allocator.hpp): 0.46 s of CPU for any command. `validate` needs none of these
/// libraries: this program links only the scene checks (apps/scene, run::preflight, mesh/),
/// with --as-needed, and validates a CI scene in a few hundredths of a second
/// (docs/reliability.md). Under mpirun every command goes to the solver, as before.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "apps/cli/allocator.hpp"
#include "apps/cli/exit_codes.hpp"
#include "apps/cli/validate_command.hpp"
#include "apps/version.hpp"
#include "parallel/mpi_session.hpp"

namespace {

/// `tetfsi validate ...` without mpirun: the validate subcommand of commands.cpp, alone.
int validate_here(int argc, char** argv) {
  using namespace tetfsi;
  CLI::App app{"tetfsi: fluids coupled two-way with deformable solids."};
  app.require_subcommand(1);
  cli::ValidateArgs args;
  add_validate_command(app, args);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  return cli::validate(args, 1);
}

/// Replaces this process by tetfsi-solver with the same arguments (and huge pages, allocator.hpp).
[[noreturn]] void exec_solver(char** argv) {
  namespace fs = std::filesystem;
  const fs::path solver = fs::read_symlink("/proc/self/exe").parent_path() / "tetfsi-solver";
  tetfsi::cli::request_huge_pages();
  execv(solver.c_str(), argv);
  throw tetfsi::run::RunError(fmt::format("cannot start {}: {}", solver.string(), std::strerror(errno)));
}

}  // namespace

int main(int argc, char** argv) {
  using namespace tetfsi;
  return cli::with_exit_codes(
      [&] {
        if (argc >= 2 && std::strcmp(argv[1], "validate") == 0 && !parallel::launched_by_mpirun())
          return validate_here(argc, argv);
        exec_solver(argv);
      },
      [](int code, const std::string& message, bool) {
        std::cerr << message << std::flush;
        return code;
      });
}
