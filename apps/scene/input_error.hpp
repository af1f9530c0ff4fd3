#pragma once
/// @file input_error.hpp
/// InputError: the scene or an input file is wrong (exit code 2, apps/cli/exit_codes.hpp). Defined
/// here, below the run framework, so that the scene's typed readers (time_step_policy.hpp) raise it
/// too; apps/run/errors.hpp names it run::InputError beside RunError.
#include <stdexcept>

namespace tetfsi::scene {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace tetfsi::scene
