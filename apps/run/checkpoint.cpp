#include "apps/run/checkpoint.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <regex>

#include <fmt/format.h>

#include "apps/run/errors.hpp"
#include "mesh/io/atomic_file.hpp"

namespace tetfsi::run {
namespace fs = std::filesystem;
namespace {

constexpr char kMagic[8] = {'T', 'E', 'T', 'F', 'S', 'I', 'C', 'K'};
constexpr int kKept = 2;  ///< checkpoints kept in the folder (the newest ones)

/// The checkpoints in DIR/checkpoint, oldest first (by frame number in the name).
std::vector<fs::path> checkpoint_files(const fs::path& out_dir) {
  static const std::regex name(R"(checkpoint_[0-9]{5}\.bin)");
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(checkpoint_folder(out_dir), ec))
    if (e.is_regular_file(ec) && std::regex_match(e.path().filename().string(), name)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

void write_output_state(BinaryWriter& w, const Output::State& s) {
  w(std::uint64_t(s.pvd_entries.size()));
  for (const auto& [object, entries] : s.pvd_entries) {
    w(object, std::uint64_t(entries.size()));
    for (const auto& [time, file] : entries) w(time, file);
  }
  w(std::uint64_t(s.bytes.vtu), std::uint64_t(s.bytes.surfaces), std::uint64_t(s.bytes.volumes), s.voxel_size,
    s.surface_scale.voxel_size, s.surface_scale.smoothing, s.stats_bytes, s.probes_bytes);
}

void read_output_state(BinaryReader& r, Output::State& s) {
  const std::size_t objects = r.count(8);
  for (std::size_t k = 0; k < objects; ++k) {
    std::string object;
    r(object);
    auto& entries = s.pvd_entries[object];
    entries.resize(r.count(16));
    for (auto& [time, file] : entries) r(time, file);
  }
  std::uint64_t vtu = 0, surfaces = 0, volumes = 0;
  r(vtu, surfaces, volumes, s.voxel_size, s.surface_scale.voxel_size, s.surface_scale.smoothing, s.stats_bytes,
    s.probes_bytes);
  s.bytes.vtu = vtu, s.bytes.surfaces = surfaces, s.bytes.volumes = volumes;
}

}  // namespace

std::uint64_t fnv1a(const char* data, std::size_t size) {
  std::uint64_t hash = 1469598103934665603ull;
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ static_cast<unsigned char>(data[i])) * 1099511628211ull;
  return hash;
}

std::uint64_t fnv1a(const std::string& text) { return fnv1a(text.data(), text.size()); }

std::uint64_t checkpoint_scene_hash(const scene::Json& resolved) {
  scene::Json j = resolved;
  if (j.contains("simulation")) j["simulation"].erase("end_time");
  // The thread count changes no result (tests/apps/test_checkpoint_resume.cpp, threads 1 and 2):
  // hashed as the default, so a checkpoint of a scene without `threads` keeps its hash.
  if (j.contains("simulation") && j["simulation"].contains("threads")) j["simulation"]["threads"] = 0;
  if (j.contains("export")) j["export"].erase("checkpoint_every");
  return fnv1a(j.dump(2));
}

fs::path checkpoint_folder(const fs::path& out_dir) { return out_dir / "checkpoint"; }

fs::path write_checkpoint(const fs::path& out_dir, std::uint64_t scene_hash, const std::string& runner,
                          const DriverState& state, const Simulation& sim, std::uintmax_t& bytes) {
  // The runner's state goes straight into the payload after its length, patched afterwards: one
  // copy of the state in memory (the flagship's is 14 MB).
  BinaryWriter payload;
  payload(state.time, std::int64_t(state.step), state.frame, state.frames_written);
  write_output_state(payload, state.output);
  payload(state.warned);
  const std::size_t at = payload.bytes().size();
  payload(std::uint64_t(0));
  sim.write_checkpoint(payload);
  const std::uint64_t runner_size = payload.bytes().size() - at - sizeof(std::uint64_t);
  std::memcpy(payload.bytes().data() + at, &runner_size, sizeof runner_size);
  BinaryWriter header;
  header.raw(kMagic, sizeof kMagic);
  header(kCheckpointVersion, scene_hash, runner, std::uint64_t(payload.bytes().size()), fnv1a(payload.bytes()));
  const fs::path folder = checkpoint_folder(out_dir);
  std::error_code ec;
  fs::create_directories(folder, ec);
  const fs::path path = folder / fmt::format("checkpoint_{:05d}.bin", state.frame);
  try {
    mesh::io::write_file_atomically(path, [&](std::ostream& out) {
      out.write(header.bytes().data(), static_cast<std::streamsize>(header.bytes().size()));
      out.write(payload.bytes().data(), static_cast<std::streamsize>(payload.bytes().size()));
    });
  } catch (const std::exception& e) {
    throw RunError(fmt::format("cannot write the checkpoint {}: {}", path.string(), e.what()));
  }
  bytes = header.bytes().size() + payload.bytes().size();
  std::vector<fs::path> files = checkpoint_files(out_dir);
  for (int k = 0; k + kKept < static_cast<int>(files.size()); ++k) fs::remove(files[k], ec);
  return path;
}

void parse_checkpoint(LoadedCheckpoint& c, std::uint64_t scene_hash, const std::string& runner,
                      const std::string& earlier) {
  const std::string name = c.file.string();
  const std::string& bytes = c.bytes;
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw InputError(fmt::format("--resume: {} is not a tetfsi checkpoint{}", name, earlier));
  try {
    BinaryReader r(bytes, name);
    char magic[sizeof kMagic];
    r.raw(magic, sizeof magic);
    std::uint32_t version = 0;
    r(version);
    if (version != kCheckpointVersion)
      throw InputError(fmt::format("--resume: {} has checkpoint format version {}; this tetfsi reads version {}: "
                                   "resume it with the tetfsi that wrote it, or run without --resume",
                                   name, version, kCheckpointVersion));
    std::uint64_t hash = 0, size = 0, payload_hash = 0;
    std::string written_by;
    r(hash);
    if (hash != scene_hash)
      throw InputError(fmt::format("--resume: {} was written for another scene (resolved-scene hash {:016x}, this one "
                                   "{:016x}; only simulation.end_time, simulation.threads and export.checkpoint_every may "
                                   "change): run without --resume to start over", name, hash, scene_hash));
    r(written_by);
    if (written_by != runner)
      throw InputError(fmt::format("--resume: {} was written by the {} runner, this scene runs on the {} runner", name,
                                   written_by, runner));
    r(size, payload_hash);
    if (size != r.left()) r.fail(fmt::format("a payload of {} bytes where {} are left", size, r.left()));
    if (fnv1a(r.here(), r.left()) != payload_hash) r.fail("a payload whose hash does not match");
    BinaryReader p(r.here(), r.left(), name);
    const std::size_t payload_offset = r.position();
    std::int64_t step = 0;
    p(c.driver.time, step, c.driver.frame, c.driver.frames_written);
    c.driver.step = step;
    read_output_state(p, c.driver.output);
    p(c.driver.warned);
    c.runner_size = p.count(1);
    c.runner_offset = payload_offset + p.position();
    p.skip(c.runner_size);
    if (p.left() != 0) p.fail("trailing bytes");
  } catch (const BinaryReadError& e) {
    throw InputError(std::string("--resume: ") + e.what() + earlier);
  }
}

LoadedCheckpoint read_latest_checkpoint(const fs::path& out_dir, std::uint64_t scene_hash, const std::string& runner) {
  const std::vector<fs::path> files = checkpoint_files(out_dir);
  if (files.empty())
    throw InputError(fmt::format("--resume: no checkpoint in {} (checkpoint_NNNNN.bin): the run wrote none "
                                 "(export.checkpoint_every is 0, or it stopped before its first); run without --resume",
                                 checkpoint_folder(out_dir).string()));
  LoadedCheckpoint c;
  c.file = files.back();
  const std::string name = c.file.string();
  const std::string earlier = files.size() > 1 ? fmt::format(" (the earlier checkpoint {} is there too: remove this "
                                                             "one to resume from it)", files[files.size() - 2].string())
                                               : std::string();
  {
    std::ifstream in(c.file, std::ios::binary);
    if (!in) throw InputError(fmt::format("--resume: cannot read {}", name));
    c.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  parse_checkpoint(c, scene_hash, runner, earlier);
  return c;
}

}  // namespace tetfsi::run
