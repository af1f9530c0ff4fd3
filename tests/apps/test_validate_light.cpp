// `tetfsi validate` runs in the light front program (apps/cli/front.cpp), which must not load the
// solver libraries (their loading alone cost about 0.25 s of CPU a start, issue 44): the work is
// bounded by what the program can load, not by a time. And it must give the verdict of the full
// program (tetfsi-solver validate, the same checks as `tetfsi run`) on every committed scene.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "tests/test_support.hpp"

namespace fs = std::filesystem;

namespace {

std::string run(const std::string& binary, const std::string& args, int* status) {
  return tetfsi::test::run_command(binary + " " + args + " 2>&1", status);
}

}  // namespace

// The shared libraries `tetfsi` loads at start (ldd: the whole dependency tree): none of the MPI,
// PETSc, hypre or OpenVDB ones, so validate can neither initialise MPI or PETSc nor pay their
// loading; the solver program does load them (the check can fail).
TEST(ValidateLight, FrontProgramLoadsNoSolverLibrary) {
  int status = -1;
  const std::string front = tetfsi::test::run_command("ldd " + std::string(TETFSI_BINARY), &status);
  ASSERT_EQ(status, 0) << front;
  const std::string solver = tetfsi::test::run_command("ldd " + std::string(TETFSI_SOLVER_BINARY), &status);
  ASSERT_EQ(status, 0) << solver;
  for (const char* lib : {"libpetsc", "libHYPRE", "libmpi", "libopenvdb"}) {
    EXPECT_EQ(front.find(lib), std::string::npos) << lib << " in\n" << front;
    EXPECT_NE(solver.find(lib), std::string::npos) << lib << " not in\n" << solver;
  }
}

// Every committed scene, a missing file and a malformed scene: the same output and exit code from
// `tetfsi validate` and `tetfsi-solver validate`; the other commands go to the solver.
TEST(ValidateLight, SameVerdictAsTheSolverProgram) {
  std::vector<std::string> args;
  for (const auto& e : fs::directory_iterator(fs::path(TETFSI_SOURCE_DIR) / "data" / "scenes"))
    if (e.path().extension() == ".json") args.push_back("validate " + e.path().string());
  args.push_back("validate missing_scene.json");
  tetfsi::test::TempDir dir("validate_light");
  const fs::path bad = dir.path() / "bad.json";
  std::ofstream(bad) << R"({"simulation": {"end_time": -1}, "solids": []})";
  args.push_back("validate " + bad.string());
  args.push_back("validate --end-time 0 " + (fs::path(TETFSI_SOURCE_DIR) / "data" / "scenes" / "cantilever.json").string());
  for (const auto& a : args) {
    SCOPED_TRACE(a);
    int front_status = -1, solver_status = -2;
    const std::string front = run(TETFSI_BINARY, a, &front_status);
    const std::string solver = run(TETFSI_SOLVER_BINARY, a, &solver_status);
    EXPECT_EQ(front_status, solver_status);
    EXPECT_EQ(front, solver);
  }
  int status = -1;
  EXPECT_NE(run(TETFSI_BINARY, "--version", &status).find("tetfsi"), std::string::npos);
  EXPECT_EQ(status, 0);
  run(TETFSI_BINARY, "frobnicate", &status);
  EXPECT_EQ(status, 2);
}
