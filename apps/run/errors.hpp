#pragma once
/// @file errors.hpp
/// The two kinds of failure the command line tells apart (exit codes in apps/cli/main.cpp):
/// InputError: the scene or an input file is wrong (exit 2; apps/scene/input_error.hpp, so the
/// scene readers raise it too); RunError: the run failed, e.g. the state diverged (exit 1).
/// Anything else thrown is reported as an internal error (exit 1).
#include <stdexcept>

#include "apps/scene/input_error.hpp"

namespace tetfsi::run {

using scene::InputError;

struct RunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace tetfsi::run
