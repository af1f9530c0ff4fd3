// Checkpoint and resume (apps/run/checkpoint.hpp) through the built tetfsi binary: a run stopped
// early (--end-time) or killed with SIGKILL, then `run --resume`d to the end, writes every frame
// file (.vtu, .ply), every .pvd, probes.csv and the model columns of stats.csv byte for byte as an
// uninterrupted run does (a coupled smoke scene, a coupled liquid scene, both with the velocity
// on particles too, an MPM scene, the fluid and solid runners); a resume
// with a changed scene, a missing, corrupt or other-version checkpoint, or on a runner that
// writes none is refused with exit code 2 naming the key or file.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <thread>
#include <tuple>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace tetfsi::test;

namespace {

const fs::path kScenes = fs::path(TETFSI_SOURCE_DIR) / "data" / "scenes";

std::string run_tetfsi(const std::string& args, int* status) {
  return run_command(std::string(TETFSI_BINARY) + " " + args + " 2>&1", status);
}

/// data/scenes/<name>.json with `patch` applied, written to `file`.
void write_variant(const std::string& name, const fs::path& file, const std::function<void(json&)>& patch) {
  std::ifstream in(kScenes / (name + ".json"));
  json scene = json::parse(in);
  patch(scene);
  std::ofstream(file) << scene.dump(2);
}

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// "run -q SCENE --out OUT --end-time T".
std::string fmt_args(const fs::path& scene, const fs::path& out, double end_time) {
  std::ostringstream s;
  s.precision(17);
  s << "run -q " << scene.string() << " --out " << out.string() << " --end-time " << end_time;
  return s.str();
}

/// Every output file of a run folder but run.log, stats.csv and the checkpoints, by relative path.
std::map<std::string, fs::path> output_files(const fs::path& dir) {
  std::map<std::string, fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), dir).string();
    if (rel == "run.log" || rel == "stats.csv" || rel.rfind("checkpoint/", 0) == 0) continue;
    files[rel] = e.path();
  }
  return files;
}

/// The cells of a CSV file's lines, as text.
std::vector<std::vector<std::string>> cells(const fs::path& file) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& line : lines(bytes_of(file))) {
    std::vector<std::string> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

/// B (interrupted and resumed) wrote what A (uninterrupted) wrote: the same frame, surface and
/// .pvd files and probes.csv byte for byte, and stats.csv with the same rows, equal in every
/// column but the wall times (t_*).
void expect_same_run(const fs::path& a, const fs::path& b) {
  const auto fa = output_files(a), fb = output_files(b);
  ASSERT_GT(fa.size(), 3u);
  std::vector<std::string> names_a, names_b;
  for (const auto& [rel, p] : fa) names_a.push_back(rel);
  for (const auto& [rel, p] : fb) names_b.push_back(rel);
  ASSERT_EQ(names_a, names_b);
  int compared = 0;
  for (const auto& [rel, p] : fa) {
    EXPECT_TRUE(bytes_of(p) == bytes_of(fb.at(rel))) << rel << " differs";
    ++compared;
  }
  const auto sa = cells(a / "stats.csv"), sb = cells(b / "stats.csv");
  ASSERT_EQ(sa.size(), sb.size());
  ASSERT_FALSE(sa.empty());
  const std::vector<std::string>& header = sa[0];
  ASSERT_EQ(header, sb[0]);
  for (std::size_t r = 1; r < sa.size(); ++r) {
    ASSERT_EQ(sa[r].size(), sb[r].size()) << "stats.csv row " << r;
    for (std::size_t c = 0; c < sa[r].size() && c < header.size(); ++c) {
      if (header[c].rfind("t_", 0) != 0) {
        EXPECT_EQ(sa[r][c], sb[r][c]) << "stats.csv row " << r << ", " << header[c];
      }
    }
  }
  std::printf("[resume] %d files and %zu stats rows identical\n", compared, sa.size() - 1);
}

/// Runs `scene` to the end into `a` (`args`: more options).
void run_uninterrupted(const fs::path& scene, const fs::path& a, const std::string& args = "") {
  int status = -1;
  const std::string log = run_tetfsi("run -q " + scene.string() + " --out " + a.string() + args, &status);
  ASSERT_EQ(status, 0) << log;
}

/// Runs B to `stop`, then --resume'd to the end; compares it with the uninterrupted run `a`.
/// `stop_args`, `resume_args`: more options of the two runs.
void check_stop_and_resume(const fs::path& scene, double stop, const fs::path& a, const fs::path& b,
                           const std::string& stop_args = "", const std::string& resume_args = "") {
  int status = -1;
  std::string log = run_tetfsi(fmt_args(scene, b, stop) + stop_args, &status);
  ASSERT_EQ(status, 0) << log;
  ASSERT_TRUE(fs::exists(b / "checkpoint")) << log;
  log = run_tetfsi("run -q " + scene.string() + " --out " + b.string() + " --resume" + resume_args, &status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(bytes_of(b / "run.log").find("resumed from"), std::string::npos);
  expect_same_run(a, b);
}

/// Starts the run of `scene` into `b`, kills it with SIGKILL as soon as its checkpoint of frame 1
/// exists, then --resume's it to the end; compares it with the uninterrupted run `a`.
void check_kill_and_resume(const fs::path& scene, const fs::path& a, const fs::path& b) {
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1), ::dup2(null, 2);
    ::execl(TETFSI_BINARY, TETFSI_BINARY, "run", "-q", scene.c_str(), "--out", b.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Waits for the checkpoint or the end of the run, however long the run takes on a loaded
  // machine (no clock: ctest's time limit ends a hang).
  const fs::path first = b / "checkpoint" / "checkpoint_00001.bin";
  int wstatus = 0;
  bool ended = false;
  while (!fs::exists(first) && !(ended = ::waitpid(pid, &wstatus, WNOHANG) == pid))
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  if (!ended) ::kill(pid, SIGKILL), ::waitpid(pid, &wstatus, 0);
  ASSERT_TRUE(WIFSIGNALED(wstatus)) << "the run ended before it was killed";
  ASSERT_TRUE(fs::exists(first));
  int status = -1;
  const std::string log = run_tetfsi("run -q " + scene.string() + " --out " + b.string() + " --resume", &status);
  ASSERT_EQ(status, 0) << log;
  expect_same_run(a, b);
}

/// data/scenes/<name>.json ending at `end` with checkpoints every `every` frames (and `patch`):
/// check_stop_and_resume with B stopped at `stop`.
void check_variant(const std::string& name, double end, double stop, int every,
                   const std::function<void(json&)>& patch = {}) {
  TempDir dir("ckpt_" + name);
  const fs::path scene = dir.path() / "scene.json";
  write_variant(name, scene, [&](json& s) {
    s["simulation"]["end_time"] = end;
    s["export"]["checkpoint_every"] = every;
    if (patch) patch(s);
  });
  run_uninterrupted(scene, dir.path() / "a");
  check_stop_and_resume(scene, stop, dir.path() / "a", dir.path() / "b");
}

}  // namespace

// Coupled runner, smoke and two deforming sheets (the flagship's CI scene), three frames: stopped
// after the first frame and resumed; killed with SIGKILL once the first checkpoint exists and
// resumed.
TEST(CheckpointResume, CoupledSmokeStoppedOrKilledResumesBitForBit) {
  TempDir dir("ckpt_smoke");
  const fs::path scene = dir.path() / "scene.json";
  write_variant("smoke_sheets_ci", scene, [](json& s) {
    s["simulation"]["end_time"] = 0.3;
    s["export"]["checkpoint_every"] = 1;
  });
  run_uninterrupted(scene, dir.path() / "a");
  check_stop_and_resume(scene, 0.1, dir.path() / "a", dir.path() / "stopped");
  check_kill_and_resume(scene, dir.path() / "a", dir.path() / "killed");
}

// Coupled runner with a free-surface liquid (level set, cut-tet system) and a rubber post.
TEST(CheckpointResume, CoupledLiquidResumesBitForBit) { check_variant("dam_break_ci", 0.15, 0.05, 1); }

// Velocity on particles (fluid/particles/): the coupled liquid on APIC particles, and the fluid
// runner's smoke on FLIP particles around the turning paddle (its mesh moved and remeshed each step).
TEST(CheckpointResume, ParticlesResumeBitForBit) {
  check_variant("dam_break_ci", 0.15, 0.05, 1, [](json& s) { s["fluid"]["advection"] = "apic"; });
  check_variant("paddle", 0.1, 0.05, 1, [](json& s) {
    s["simulation"]["frame_rate"] = 20;
    s["fluid"]["advection"] = "flip";
  });
}

// The mpm runner: gas particles, membrane and grid contact.
TEST(CheckpointResume, MpmResumesBitForBit) { check_variant("gas_expansion_ci", 1.0, 0.5, 2); }

// The fluid runner: smoke around a paddle that turns (the fluid mesh moved and remeshed each step).
TEST(CheckpointResume, FluidRunnerResumesBitForBit) {
  check_variant("paddle", 0.1, 0.05, 1, [](json& s) { s["simulation"]["frame_rate"] = 20; });
}

// The solid runner: a soft block dropped on the floor (contact), stopped mid-fall.
TEST(CheckpointResume, SolidRunnerResumesBitForBit) {
  check_variant("soft_drop", 0.5, 0.2, 2, [](json& s) { s["simulation"]["frame_rate"] = 10; });
}

// The thread count changes no result, so --resume accepts another --threads (checkpoint_scene_hash
// hashes it as 0): run with 1 thread, stopped with 2 and resumed with 1 (and the reverse), the
// output is byte for byte the uninterrupted run's. Solid runner (soft drop, contact) and coupled
// runner (the flagship's smoke and sheets).
TEST(CheckpointResume, AnotherThreadCountResumesBitForBit) {
  for (const auto& [name, end, stop] : std::vector<std::tuple<std::string, double, double>>{
           {"soft_drop", 0.4, 0.2}, {"smoke_sheets_ci", 0.2, 0.1}}) {
    SCOPED_TRACE(name);
    TempDir dir("ckpt_threads");
    const fs::path scene = dir.path() / "scene.json";
    write_variant(name, scene, [&, end = end](json& s) {
      s["simulation"]["end_time"] = end;
      s["simulation"]["frame_rate"] = 10;
      s["export"]["checkpoint_every"] = 1;
    });
    run_uninterrupted(scene, dir.path() / "a", " --threads 1");
    check_stop_and_resume(scene, stop, dir.path() / "a", dir.path() / "b", " --threads 2", " --threads 1");
    check_stop_and_resume(scene, stop, dir.path() / "a", dir.path() / "c", " --threads 1", " --threads 2");
  }
}

// What --resume refuses, with exit code 2 and the file or key named.
TEST(CheckpointResume, RefusesChangedSceneAndBadCheckpoints) {
  TempDir dir("ckpt_refuse");
  const fs::path scene = dir.path() / "gas.json", changed = dir.path() / "gas_changed.json";
  write_variant("gas_expansion_ci", scene, [](json& s) {
    s["simulation"]["end_time"] = 0.5;
    s["export"]["checkpoint_every"] = 1;
  });
  write_variant("gas_expansion_ci", changed, [](json& s) {
    s["simulation"]["end_time"] = 1.0;
    s["export"]["checkpoint_every"] = 1;
    s["simulation"]["gravity"] = {0.0, -1.0, 0.0};
  });
  const fs::path out = dir.path() / "out", empty = dir.path() / "empty";
  int status = -1;
  std::string log = run_tetfsi("run -q " + scene.string() + " --out " + empty.string() + " --resume", &status);
  EXPECT_EQ(status, 2) << log;
  EXPECT_NE(log.find("no checkpoint in"), std::string::npos) << log;

  log = run_tetfsi(fmt_args(scene, out, 0.5), &status);
  ASSERT_EQ(status, 0) << log;
  const fs::path file = out / "checkpoint" / "checkpoint_00002.bin";
  ASSERT_TRUE(fs::exists(file)) << log;

  log = run_tetfsi("run -q " + changed.string() + " --out " + out.string() + " --resume", &status);
  EXPECT_EQ(status, 2) << log;
  EXPECT_NE(log.find("was written for another scene"), std::string::npos) << log;
  EXPECT_NE(log.find(file.string()), std::string::npos) << log;

  log = run_tetfsi(fmt_args(scene, out, 0.5) + " --resume", &status);  // nothing left to run
  EXPECT_EQ(status, 2) << log;

  const std::string good = bytes_of(file);
  std::string bad = good;
  bad[bad.size() / 2] ^= 0x5a;  // one payload byte
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bad;
  log = run_tetfsi(fmt_args(scene, out, 1.0) + " --resume", &status);
  EXPECT_EQ(status, 2) << log;
  EXPECT_NE(log.find("truncated or corrupt"), std::string::npos) << log;
  EXPECT_NE(log.find(file.string()), std::string::npos) << log;

  bad = good;
  bad[8] = char(99);  // the format version
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bad;
  log = run_tetfsi(fmt_args(scene, out, 1.0) + " --resume", &status);
  EXPECT_EQ(status, 2) << log;
  EXPECT_NE(log.find("format version"), std::string::npos) << log;

  std::ofstream(file, std::ios::binary | std::ios::trunc) << good.substr(0, good.size() / 3);
  log = run_tetfsi(fmt_args(scene, out, 1.0) + " --resume", &status);
  EXPECT_EQ(status, 2) << log;
  EXPECT_NE(log.find("truncated or corrupt"), std::string::npos) << log;
}

// Runners that write no checkpoints refuse the key (validate and run alike) and --resume.
TEST(CheckpointResume, RunnersWithoutCheckpointsRefuse) {
  TempDir dir("ckpt_runner");
  const fs::path scene = dir.path() / "hex.json", off = dir.path() / "hex_off.json";
  write_variant("hex_rotated_cantilever", scene, [](json& s) { s["export"]["checkpoint_every"] = 1; });
  write_variant("hex_rotated_cantilever", off, [](json&) {});
  int status = -1;
  for (const std::string& cmd : std::vector<std::string>{"validate ", "run -q --out " + (dir.path() / "o").string() + " "}) {
    const std::string log = run_tetfsi(cmd + scene.string(), &status);
    EXPECT_EQ(status, 2) << log;
    EXPECT_NE(log.find("/export/checkpoint_every"), std::string::npos) << log;
  }
  const std::string log = run_tetfsi("run -q --resume --out " + (dir.path() / "o").string() + " " + off.string(), &status);
  EXPECT_EQ(status, 2) << log;
  EXPECT_NE(log.find("does not write checkpoints"), std::string::npos) << log;
}
