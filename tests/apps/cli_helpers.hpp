#pragma once
/// @file cli_helpers.hpp
/// Helpers of the tests that run the tetfsi binary (TETFSI_BINARY, tetfsi_apps_cli_test) on the
/// committed scenes.
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/test_support.hpp"

namespace tetfsi::test {

/// Runs `tetfsi ARGS` with stderr joined to stdout; returns the output, `status` the exit code.
inline std::string tetfsi_cmd(const std::string& args, int* status) {
  return run_command(std::string(TETFSI_BINARY) + " " + args + " 2>&1", status);
}

/// The committed scene data/scenes/NAME, parsed.
inline nlohmann::json committed(const std::string& name) {
  std::ifstream in(std::filesystem::path(TETFSI_SOURCE_DIR) / "data" / "scenes" / name);
  return nlohmann::json::parse(in);
}

}  // namespace tetfsi::test
