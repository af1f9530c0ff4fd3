#pragma once
/// @file validate_command.hpp
/// `tetfsi validate SCENE`: its command-line options and the command. Shared by the full program
/// (commands.cpp) and the light front program (front.cpp, which runs validate without loading the
/// solver libraries).
#include <string>

#include <CLI/CLI.hpp>

#include "apps/run/run_options.hpp"

namespace tetfsi::cli {

struct ValidateArgs {
  run::RunOptions options;
  bool print_resolved = false;  ///< --resolved
  double end_time = 0, max_tets = 0;
  CLI::Option* end_time_option = nullptr;
  CLI::Option* max_tets_option = nullptr;
};

/// The help of --max-tets (run, validate, mesh).
std::string max_tets_help();

/// Adds the `validate` subcommand with its options, parsed into `args`.
CLI::App* add_validate_command(CLI::App& app, ValidateArgs& args);

/// The scene checks and every check of run::preflight (the ones `tetfsi run` makes before it
/// meshes), so that both give the same verdict; `processes`: MPI processes of the run (1 without
/// mpirun). Prints the verdict; returns 0 (a problem is thrown: SceneError or InputError, exit 2).
int validate(ValidateArgs& args, int processes);

}  // namespace tetfsi::cli
