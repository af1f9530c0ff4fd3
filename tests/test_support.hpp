#pragma once
/// @file test_support.hpp
/// Small helpers shared by tests: temporary folders and running a command for its output.
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace tetfsi::test {

/// A fresh, empty folder under the system temp folder, removed when the object goes away.
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    path_ = std::filesystem::temp_directory_path() /
            ("tetfsi_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  static int& counter() {
    static int c = 0;
    return c;
  }
  std::filesystem::path path_;
};

/// Runs a shell command, returns its standard output; `status` receives the exit code.
inline std::string run_command(const std::string& command, int* status = nullptr) {
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int rc = ::pclose(pipe);
  if (status) *status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  return out;
}

/// Describes a .vtu/.pvd with VTK's own reader (tests/tools/vtu_info.py): "points cells fields";
/// with `sums`, each field also gives the sum of its values as VTK decoded them.
inline std::string vtk_describe(const std::filesystem::path& file, int* status = nullptr, bool sums = false) {
  return run_command(std::string(TETFSI_PYTHON) + " " + TETFSI_SOURCE_DIR + "/tests/tools/vtu_info.py " +
                         (sums ? "--sums '" : "'") + file.string() + "'",
                     status);
}

/// Whether VTK's Python bindings (Debian python3-vtk9) import in the interpreter the tests use.
inline bool vtk_available() {
  int status = -1;
  run_command(std::string(TETFSI_PYTHON) + " -c 'import vtk' > /dev/null 2>&1", &status);
  return status == 0;
}

}  // namespace tetfsi::test
