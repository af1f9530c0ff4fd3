#pragma once
/// @file output.hpp
/// The output folder of a run: per-object .pvd collections with a .vtu per frame, per-frame
/// surfaces (PLY/OBJ), per-frame fluid volumes (OpenVDB), stats.csv and probes.csv. Every frame file is written atomically (temp
/// file + rename) and a .pvd only lists frames already complete, so an interrupted run leaves
/// whole frames. Before a run writes anything, clean_output_folder removes orphan temporary files
/// (of a killed run) and, in a folder that holds an earlier run, that run's frames, .pvd and CSV
/// files, so no stale frame is left beside the new .pvd; other files are never deleted.
#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "apps/scene/scene.hpp"
#include "fluid/io/voxel_sampling.hpp"
#include "mesh/io/vtu_writer.hpp"
#include "mesh/surface_mesh.hpp"

namespace tetfsi::run {

class Output {
 public:
  /// Creates `dir` (and parents) if needed. `export_cfg` is the resolved /export block.
  Output(std::filesystem::path dir, scene::Json export_cfg);

  const std::filesystem::path& dir() const { return dir_; }
  /// Whether frame `frame` is written at all (export.every_n_frames).
  bool frame_due(int frame) const;

  /// Writes <object>/<object>_<frame>.vtu (compressed as export.compression says, fields of the
  /// type export.precision says, turned as
  /// export.up_axis says: points and every 3-component field) and lists it in <object>.pvd at
  /// `time` [s] (nothing if export.vtu is false).
  void write_grid(const std::string& object, int frame, double time,
                  const mesh::io::UnstructuredGrid& grid);
  /// Writes surfaces/<object>_<frame>.ply (with per-vertex velocity [m/s] if given) or .obj,
  /// as export.surfaces says, turned as export.up_axis says.
  void write_surface(const std::string& object, int frame, const mesh::SurfaceMesh& surface,
                     const std::vector<Eigen::Vector3d>& velocity = {});

  /// Whether export.volumes asks for volume files ("vdb").
  bool volumes() const { return volumes_; }
  /// Voxel edge of the volume files [m]: export.voxel_size, else half of `mean_edge_length` at
  /// the first call, kept for the rest of the run (one transform for every frame).
  double voxel_size(double mean_edge_length);
  /// The voxel size fixed so far [m] (0 before the first volume frame without export.voxel_size).
  double fixed_voxel_size() const { return voxel_size_; }
  /// Writes volumes/<object>_<frame>.vdb (fluid/io/vdb_writer.hpp) from `samples` and, if not
  /// null, the level set of the closed liquid `surface`, turned as export.up_axis says: "z" maps
  /// voxel (i, j, k) to (i, -k, j) (a lattice point again, no resampling) and vectors alike.
  void write_volumes(const std::string& object, int frame, fluid::VoxelSamples samples,
                     const mesh::SurfaceMesh* surface);

  /// Whether export.liquid_surface.type is "smooth" (fluid/io/render_surface.hpp), not "tets".
  bool smooth_liquid_surface() const { return smooth_surface_; }
  /// Length scales of the smooth liquid surface [m].
  struct SurfaceScale {
    double voxel_size = 0, smoothing = 0;
  };
  /// export.liquid_surface's voxel_size and smoothing; where absent, fixed at the first call with a
  /// positive `cut_edge` (write_fluid_frame passes the 10th percentile of the mean edge lengths of
  /// the tets the surface cuts: the finest the simulation resolves the surface, in a mesh refined
  /// near solids or at the surface) [m]: smoothing = cut_edge, voxel_size = smoothing / 4
  /// (cut_edge / 4 with smoothing 0), kept for the rest of the run.
  /// @throws InputError naming /export/liquid_surface/smoothing if it exceeds
  ///         scene::kMaxSmoothingVoxels voxels
  SurfaceScale liquid_surface_scale(double cut_edge);
  /// The scale fixed so far (zeros before the first smooth surface without both keys).
  const SurfaceScale& surface_scale() const { return surface_scale_; }
  /// Records the relative error |V_surface / V_liquid - 1| of a frame's smooth surface.
  void note_surface_volume_error(double relative) { surface_volume_error_ = std::max(surface_volume_error_, relative); }
  /// The largest error noted so far.
  double surface_volume_error() const { return surface_volume_error_; }

  /// Starts stats.csv with the given header (replacing the file of an earlier run).
  void begin_stats(const std::vector<std::string>& header);
  /// Appends one row; each row goes out in a single write, flushed.
  void stats_row(const std::vector<double>& row);
  /// Same for probes.csv (only created when the scene has probes).
  void begin_probes(const std::vector<std::string>& header);
  void probes_row(const std::vector<double>& row);

  /// Bytes of the frame files written so far: .vtu frames, surface and volume files (for run.log).
  struct Bytes {
    std::uintmax_t vtu = 0, surfaces = 0, volumes = 0;
    std::uintmax_t total() const { return vtu + surfaces + volumes; }
  };
  const Bytes& bytes_written() const { return bytes_; }

  /// What a checkpoint keeps of the output (checkpoint.hpp): the frames each .pvd lists, the bytes
  /// written, the voxel size fixed, and the length of stats.csv and probes.csv [bytes].
  struct State {
    std::map<std::string, std::vector<std::pair<double, std::string>>> pvd_entries;  ///< (time, file) per object
    Bytes bytes;
    double voxel_size = 0;
    SurfaceScale surface_scale;  ///< fixed by liquid_surface_scale (0: not yet)
    std::uint64_t stats_bytes = 0, probes_bytes = 0;
  };
  State state() const;
  /// Continues the output of a checkpointed run (`tetfsi run --resume`): rewrites every .pvd with
  /// the frames it listed then, and reopens stats.csv and probes.csv cut back to their length then
  /// (rows written after the checkpoint are dropped), checking their header is `header` /
  /// `probes_header` (empty: no probes.csv). @throws InputError naming the file if it is missing,
  /// shorter than recorded or has another header
  void resume(const State& state, const std::vector<std::string>& header, const std::vector<std::string>& probes_header);

 private:
  std::filesystem::path dir_;
  scene::Json cfg_;
  std::map<std::string, std::unique_ptr<mesh::io::PvdCollection>> pvds_;
  std::map<std::string, std::vector<std::pair<double, std::string>>> pvd_entries_;  ///< what each .pvd lists
  std::uint64_t stats_bytes_ = 0, probes_bytes_ = 0;  ///< bytes written to stats.csv, probes.csv
  std::ofstream stats_, probes_;
  mesh::io::VtuCompression compression_;
  mesh::io::VtuPrecision precision_;  ///< of the point and cell fields (export.precision)
  bool z_up_ = false;  ///< export.up_axis "z": turn positions and vectors (x, y, z) -> (x, -z, y)
  bool volumes_ = false;
  double voxel_size_ = 0;  ///< 0 until fixed by voxel_size()
  bool smooth_surface_ = true;
  SurfaceScale surface_scale_;  ///< 0 until fixed by liquid_surface_scale()
  double surface_volume_error_ = 0;
  Bytes bytes_;
};

/// What clean_output_folder removed.
struct OutputCleanup {
  int temporary_files = 0;    ///< *.tmp.<pid> files of interrupted atomic writes
  int earlier_run_files = 0;  ///< frames (<object>/<object>_NNNNN.vtu, surfaces/<object>_NNNNN.ply|obj,
                              ///< volumes/<object>_NNNNN.vdb),
                              ///< *.pvd, stats.csv, probes.csv, checkpoints of an earlier run (with
                              ///< resume_frame: the frames after the checkpoint)
};

/// Prepares an output folder: removes orphan temporary files (everywhere in `dir` and its
/// sub-folders) and, if `earlier_run` (the folder holds a run.log), the files an earlier run wrote
/// (the names listed in OutputCleanup, and its checkpoints checkpoint/checkpoint_NNNNN.bin), and
/// sub-folders left empty by that. Other files stay. `resume_frame` >= 0 (`run --resume` from a
/// checkpoint at that frame): the run is continued, so only its frames numbered above
/// resume_frame (written after the checkpoint) go, with the temporary files; .pvd, CSV files and
/// checkpoints stay (Output::resume cuts the CSV files back).
OutputCleanup clean_output_folder(const std::filesystem::path& dir, bool earlier_run, int resume_frame = -1);

/// A file that `tetfsi mesh` or a run writes (atomically: `path`.tmp.<pid>, then renamed): refused
/// with InputError (exit 2) before any work if `path` is a folder or no file can be created beside
/// it (a missing or read-only folder, /proc). `what` names the option in the message.
void check_output_file(const std::filesystem::path& path, const std::string& what);

/// The output folder `dir` of a run, checked before any work: `dir` a folder (or creatable: its
/// nearest existing parent a folder), a new file can be written in it, and none of the paths the run
/// writes is taken by the wrong kind of entry: `<object>` (each of `objects`), `surfaces`,
/// `volumes`, `checkpoint` not files; `<object>.pvd`, stats.csv, probes.csv, run.log and the frame
/// files already in those folders not folders. @throws InputError naming the path (exit 2)
void check_output_folder(const std::filesystem::path& dir, const std::vector<std::string>& objects);

/// One CSV row of numbers (17 significant digits, so values read back exactly); a non-finite
/// value (a probe without a value) is an empty cell.
std::string csv_row(const std::vector<double>& row);

}  // namespace tetfsi::run
