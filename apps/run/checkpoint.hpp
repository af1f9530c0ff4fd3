#pragma once
/// @file checkpoint.hpp
/// Checkpoints of a run (export.checkpoint_every; `tetfsi run SCENE --out DIR --resume`): after
/// every checkpoint_every-th frame the driver writes DIR/checkpoint/checkpoint_NNNNN.bin (NNNNN
/// the frame), atomically (mesh/io/atomic_file.hpp), keeping the newest two. A file is
///
///     "TETFSICK"  magic, 8 bytes
///     u32         format version (kCheckpointVersion)
///     u64         scene hash: FNV-1a of the resolved scene without simulation.end_time and
///                 export.checkpoint_every, simulation.threads hashed as 0 (checkpoint_scene_hash),
///                 so a run may be resumed with a later end time or another thread count, and
///                 nothing else may change
///     string      runner name (u64 length + bytes)
///     u64, u64    payload length and its FNV-1a hash (a damaged payload is found before parsing)
///     payload     the driver's state (DriverState: time, step, frame, the output's .pvd lists,
///                 bytes, voxel size and CSV lengths, warned probes) and the runner's
///                 (Simulation::write_checkpoint) as a string
///
/// in the machine's byte order (support/binary_stream.hpp). --resume re-runs the runner's
/// setup() (meshing included: it is deterministic) and then overwrites its state with the
/// checkpoint's, so the steps after it are bit for bit those of an uninterrupted run.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/run/output.hpp"
#include "apps/run/simulation.hpp"

namespace tetfsi::run {

constexpr std::uint32_t kCheckpointVersion = 8;  // 8: the smooth liquid surface's scale in the output state

/// FNV-1a 64-bit hash of a text.
std::uint64_t fnv1a(const std::string& text);
std::uint64_t fnv1a(const char* data, std::size_t size);

/// The hash a checkpoint is tied to: of the resolved scene (JSON dump, 2-space indent) without
/// /simulation/end_time and /export/checkpoint_every, with /simulation/threads as 0 (the results
/// do not depend on it).
std::uint64_t checkpoint_scene_hash(const scene::Json& resolved);

/// The driver's part of a checkpoint: where the time loop stands after a frame.
struct DriverState {
  double time = 0;        ///< t [s]
  long step = 0;          ///< steps taken
  int frame = 0;          ///< the last frame index reached
  int frames_written = 0; ///< frames written (export.every_n_frames)
  Output::State output;
  std::vector<std::uint64_t> warned;  ///< probes whose missing value was logged
};

/// DIR/checkpoint.
std::filesystem::path checkpoint_folder(const std::filesystem::path& out_dir);

/// Writes the checkpoint of frame state.frame and removes all but the newest two.
/// @return its path; `bytes` is set to its size
std::filesystem::path write_checkpoint(const std::filesystem::path& out_dir, std::uint64_t scene_hash,
                                       const std::string& runner, const DriverState& state, const Simulation& sim,
                                       std::uintmax_t& bytes);

/// A checkpoint read back: the driver's state and the runner's, still to be read by
/// Simulation::read_checkpoint (runner_state(), named by `file`).
struct LoadedCheckpoint {
  std::filesystem::path file;
  DriverState driver;
  std::string bytes;                     ///< the whole file
  std::size_t runner_offset = 0, runner_size = 0;  ///< where the runner's state is in it
  BinaryReader runner_state() const { return BinaryReader(bytes.data() + runner_offset, runner_size, file.string()); }
};

/// Checks and reads the checkpoint held in c.bytes (named c.file in messages): header, payload
/// hash, driver state and where the runner's state lies; `note` is appended to the errors.
/// read_latest_checkpoint reads the file and calls it; fuzz/fuzz_checkpoint.cpp feeds it bytes.
/// @throws InputError as read_latest_checkpoint
void parse_checkpoint(LoadedCheckpoint& c, std::uint64_t scene_hash, const std::string& runner,
                      const std::string& note = "");

/// Reads the newest checkpoint of DIR.
/// @throws InputError naming the folder or file: none there, not a checkpoint, another format
///         version, another scene or runner, truncated or corrupt
LoadedCheckpoint read_latest_checkpoint(const std::filesystem::path& out_dir, std::uint64_t scene_hash,
                                        const std::string& runner);

}  // namespace tetfsi::run
