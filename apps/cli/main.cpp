/// @file main.cpp
/// The `tetfsi` command line. Exit codes: 0 success, 2 invalid scene or input (bad options,
/// unreadable or malformed files), 1 the run failed (e.g. diverged) or an internal error.
/// Every exception is caught here: tetfsi reports, it does not crash.
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "apps/cli/commands.hpp"
#include "apps/run/errors.hpp"
#include "apps/scene/scene.hpp"
#include "apps/version.hpp"

int main(int argc, char** argv) {
  using namespace tetfsi;
  std::string command_line;
  for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);
  try {
    return cli::dispatch(argc, argv, command_line);
  } catch (const scene::SceneError& e) {
    std::cerr << e.what() << "\n"
              << fmt::format("{} problem(s) in the scene; nothing was run. The key reference is "
                             "`tetfsi schema` (docs/scene_format.md).\n", e.issues().size());
    return 2;
  } catch (const run::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const run::RunError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n(please report this with the scene file)\n";
    return 1;
  } catch (...) {
    std::cerr << "internal error: unknown exception\n";
    return 1;
  }
}
