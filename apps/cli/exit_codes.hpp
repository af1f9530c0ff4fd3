#pragma once
/// @file exit_codes.hpp
/// The exit codes of `tetfsi`, shared by both of its programs (main.cpp, front.cpp): 0 success,
/// 2 invalid scene or input (bad options, unreadable or malformed files), 1 the run failed (e.g.
/// diverged) or an internal error. Every exception is caught: tetfsi reports, it does not crash.
#include <exception>
#include <string>

#include <fmt/format.h>

#include "apps/run/errors.hpp"
#include "apps/scene/scene.hpp"

namespace tetfsi::cli {

/// Runs body() and returns its exit code, or the code of what it threw after passing the message
/// to fail(code, message, same_everywhere) (which prints it and returns the code);
/// `same_everywhere`: an error every MPI process meets alike (scene, input or run error).
template <class Body, class Fail>
int with_exit_codes(Body&& body, Fail&& fail) {
  try {
    return body();
  } catch (const scene::SceneError& e) {
    return fail(2, fmt::format("{}\n{} problem(s) in the scene; nothing was run. The key reference is `tetfsi schema` "
                               "(docs/scene_format.md).\n", e.what(), e.issues().size()),
                true);
  } catch (const run::InputError& e) {
    return fail(2, fmt::format("error: {}\n", e.what()), true);
  } catch (const run::RunError& e) {
    return fail(1, fmt::format("error: {}\n", e.what()), true);
  } catch (const std::exception& e) {
    return fail(1, fmt::format("internal error: {}\n(please report this with the scene file)\n", e.what()), false);
  } catch (...) {
    return fail(1, "internal error: unknown exception\n", false);
  }
}

}  // namespace tetfsi::cli
