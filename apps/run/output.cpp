#include "apps/run/output.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <regex>

#include <unistd.h>

#include <fmt/format.h>

#include "apps/run/errors.hpp"
#include "fluid/io/vdb_writer.hpp"
#include "mesh/io/atomic_file.hpp"
#include "mesh/io/ply_writer.hpp"

namespace tetfsi::run {
namespace fs = std::filesystem;
namespace {

/// +90 degrees about x: scene +y (up) becomes +z, (x, y, z) -> (x, -z, y).
Eigen::Vector3d z_up(const Eigen::Vector3d& x) { return {x.x(), -x.z(), x.y()}; }

void write_obj(const fs::path& path, const mesh::SurfaceMesh& s) {
  mesh::io::write_file_atomically(path, [&](std::ostream& out) {
    out << "# tetfsi surface, metres\n";
    for (const auto& v : s.vertices) out << fmt::format("v {:.9g} {:.9g} {:.9g}\n", v.x(), v.y(), v.z());
    for (const auto& t : s.triangles) out << fmt::format("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
  });
}

std::string csv_header(const std::vector<std::string>& header) {
  std::string line;
  for (const auto& h : header) line += (line.empty() ? "" : ",") + h;
  return line + '\n';
}

/// Creates the CSV file with its header line; returns the bytes written.
std::uint64_t open_csv(std::ofstream& f, const fs::path& path, const std::vector<std::string>& header) {
  f.open(path, std::ios::trunc);
  if (!f) throw RunError("cannot create " + path.string());
  const std::string line = csv_header(header);
  f << line << std::flush;
  return line.size();
}

/// Appends one row in a single write, flushed, and counts its bytes.
void append_row(std::ofstream& f, std::uint64_t& bytes, const std::vector<double>& row) {
  const std::string line = csv_row(row);
  f << line << std::flush;
  bytes += line.size();
}

/// Cuts the CSV file of a checkpointed run back to `length` bytes and opens it for appending.
std::uint64_t reopen_csv(std::ofstream& f, const fs::path& path, const std::vector<std::string>& header,
                         std::uint64_t length) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec) throw InputError(fmt::format("--resume: {} is missing: cannot continue the run ({})", path.string(), ec.message()));
  if (size < length)
    throw InputError(fmt::format("--resume: {} has {} bytes, fewer than the {} of the checkpoint: it is not the file of "
                                 "the checkpointed run", path.string(), size, length));
  const std::string expected = csv_header(header);
  std::string first(expected.size(), '\0');
  {
    std::ifstream in(path, std::ios::binary);
    in.read(first.data(), static_cast<std::streamsize>(first.size()));
  }
  if (first != expected)
    throw InputError(fmt::format("--resume: {} does not start with the columns of this run ({}): it is not the file of "
                                 "the checkpointed run", path.string(), expected.substr(0, expected.size() - 1)));
  fs::resize_file(path, length, ec);
  if (ec) throw InputError(fmt::format("--resume: cannot cut {} back to the checkpoint: {}", path.string(), ec.message()));
  f.open(path, std::ios::app);
  if (!f) throw RunError("cannot open " + path.string());
  return length;
}

}  // namespace

std::string csv_row(const std::vector<double>& row) {
  std::string line;
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (i) line += ',';
    if (std::isfinite(row[i])) line += fmt::format("{:.17g}", row[i]);
  }
  return line + "\n";
}

OutputCleanup clean_output_folder(const fs::path& dir, bool earlier_run, int resume_frame) {
  static const std::regex temporary(R"(.+\.tmp\.[0-9]+)");
  static const std::regex surface_frame(R"(.+_([0-9]{5})\.(ply|obj))");
  static const std::regex volume_frame(R"(.+_([0-9]{5})\.vdb)");
  static const std::regex checkpoint(R"(checkpoint_[0-9]{5}\.bin)");
  const bool resume = resume_frame >= 0;
  OutputCleanup done;
  std::error_code ec;
  auto remove = [&](const fs::path& p, int& count) {
    if (fs::remove(p, ec)) ++count;
  };
  // A frame file of the earlier run goes, unless the run is resumed and the frame is one the
  // checkpoint keeps. m[1] is the frame number.
  auto stale = [&](const std::string& name, const std::regex& pattern) {
    std::smatch m;
    if (!std::regex_match(name, m, pattern)) return false;
    return !resume || std::stoi(m[1].str()) > resume_frame;
  };
  std::vector<fs::path> folders;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (e.is_directory(ec)) {
      folders.push_back(e.path());
    } else if (e.is_regular_file(ec)) {
      if (std::regex_match(name, temporary)) remove(e.path(), done.temporary_files);
      else if (earlier_run && !resume && (e.path().extension() == ".pvd" || name == "stats.csv" || name == "probes.csv"))
        remove(e.path(), done.earlier_run_files);
    }
  }
  for (const auto& folder : folders) {
    const std::string object = folder.filename().string();
    const std::regex frame(std::regex_replace(object, std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
                           R"(_([0-9]{5})\.vtu)");
    const int before = done.earlier_run_files;
    for (const auto& e : fs::directory_iterator(folder, ec)) {
      if (!e.is_regular_file(ec)) continue;
      const std::string name = e.path().filename().string();
      if (std::regex_match(name, temporary)) remove(e.path(), done.temporary_files);
      else if (earlier_run && (stale(name, frame) || (object == "surfaces" && stale(name, surface_frame)) ||
                               (object == "volumes" && stale(name, volume_frame)) ||
                               (object == "checkpoint" && !resume && std::regex_match(name, checkpoint))))
        remove(e.path(), done.earlier_run_files);
    }
    if (done.earlier_run_files > before && fs::is_empty(folder, ec)) fs::remove(folder, ec);
  }
  return done;
}

namespace {
/// Creates and removes `path`.tmp.<pid> (the name an atomic write uses); returns why it could not
/// be created, or "".
std::string cannot_create(const fs::path& path) {
  const fs::path probe = path.string() + ".tmp." + std::to_string(::getpid());
  errno = 0;
  { std::ofstream(probe, std::ios::app); }
  std::error_code ec;
  if (fs::exists(probe, ec)) return fs::remove(probe, ec), "";
  return errno ? std::strerror(errno) : "unknown reason";
}
}  // namespace

void check_output_file(const fs::path& path, const std::string& what) {
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw InputError(fmt::format("{} {}: is a folder; give the name of a file to write", what, path.string()));
  if (const std::string why = cannot_create(path); !why.empty())
    throw InputError(fmt::format("{} {}: cannot create a file there ({}): give a path in a folder you can write",
                                 what, path.string(), why));
}

void check_output_folder(const fs::path& dir, const std::vector<std::string>& objects) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(fmt::format("--out {}: is a file, not a folder", dir.string()));
  if (!fs::exists(dir, ec)) {  // created by the run: its nearest existing parent must be a folder
    fs::path parent = fs::absolute(dir, ec);
    while (parent.has_parent_path() && parent != parent.parent_path() && !fs::exists(parent, ec))
      parent = parent.parent_path();
    if (!fs::is_directory(parent, ec))
      throw InputError(fmt::format("--out {}: cannot create the folder: {} is a file, not a folder", dir.string(),
                                   parent.string()));
    if (const std::string why = cannot_create(parent / "tetfsi_out"); !why.empty())
      throw InputError(fmt::format("--out {}: cannot create the folder in {} ({})", dir.string(), parent.string(), why));
    return;
  }
  check_output_file(dir / "run.log.check", "--out");
  auto refuse = [&](const fs::path& p, const char* is, const char* expected) {
    throw InputError(fmt::format("--out {}: {} is {}, where the run writes {}; move it away or choose another "
                                 "--out", dir.string(), p.string(), is, expected));
  };
  std::vector<std::string> folders = objects;
  for (const char* f : {"surfaces", "volumes", "checkpoint"}) folders.emplace_back(f);
  for (const auto& f : folders) {
    const fs::path p = dir / f;
    if (fs::exists(p, ec) && !fs::is_directory(p, ec)) refuse(p, "a file", "a folder of frames");
    for (const auto& e : fs::directory_iterator(p, ec))  // an earlier run's frame files (a missing folder: none)
      if (e.is_directory(ec) && std::regex_match(e.path().filename().string(), std::regex(R"(.+\.(vtu|ply|obj|vdb|bin))")))
        refuse(e.path(), "a folder", "frame files");
  }
  std::vector<std::string> files = {"stats.csv", "probes.csv", "run.log"};
  for (const auto& o : objects) files.push_back(o + ".pvd");
  for (const auto& f : files)
    if (fs::is_directory(dir / f, ec)) refuse(dir / f, "a folder", "a file");
}

Output::Output(fs::path dir, scene::Json export_cfg)
    : dir_(std::move(dir)),
      cfg_(std::move(export_cfg)),
      compression_(cfg_.at("compression") == "none" ? mesh::io::VtuCompression::None : mesh::io::VtuCompression::Zlib),
      precision_(cfg_.at("precision") == "float64" ? mesh::io::VtuPrecision::Float64 : mesh::io::VtuPrecision::Float32),
      z_up_(cfg_.at("up_axis") == "z"),
      volumes_(cfg_.value("volumes", "none") == "vdb") {
  if (cfg_.contains("voxel_size")) voxel_size_ = cfg_["voxel_size"].get<double>();
  const scene::Json surface = cfg_.value("liquid_surface", scene::Json::object());
  smooth_surface_ = surface.value("type", "smooth") == "smooth";
  if (surface.contains("smoothing")) {  // else both wait for the first frame (liquid_surface_scale)
    surface_scale_.smoothing = surface["smoothing"].get<double>();
    surface_scale_.voxel_size = surface.value("voxel_size", 0.25 * surface_scale_.smoothing);
  }
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    throw InputError(fmt::format("cannot create the output folder {}: {}", dir_.string(), ec.message()));
}

bool Output::frame_due(int frame) const {
  return frame % cfg_.at("every_n_frames").get<int>() == 0;
}

void Output::write_grid(const std::string& object, int frame, double time,
                        const mesh::io::UnstructuredGrid& grid) {
  if (!cfg_.at("vtu").get<bool>()) return;
  fs::create_directories(dir_ / object);
  const std::string rel = fmt::format("{}/{}_{:05d}.vtu", object, object, frame);
  if (z_up_) {
    mesh::io::UnstructuredGrid turned = grid;
    for (auto& x : turned.points) x = z_up(x);
    for (auto* fields : {&turned.point_data, &turned.cell_data})
      for (auto& f : *fields)
        if (f.components == 3)
          for (std::size_t i = 0; i + 2 < f.values.size(); i += 3) {
            const double y = f.values[i + 1];
            f.values[i + 1] = -f.values[i + 2];
            f.values[i + 2] = y;
          }
    bytes_.vtu += mesh::io::write_vtu(dir_ / rel, turned, compression_, precision_);
  } else {
    bytes_.vtu += mesh::io::write_vtu(dir_ / rel, grid, compression_, precision_);
  }
  auto& pvd = pvds_[object];
  if (!pvd) pvd = std::make_unique<mesh::io::PvdCollection>(dir_ / (object + ".pvd"));
  pvd->add(time, rel);  // after the frame file is complete
  pvd_entries_[object].emplace_back(time, rel);
}

void Output::write_surface(const std::string& object, int frame, const mesh::SurfaceMesh& surface,
                           const std::vector<Eigen::Vector3d>& velocity) {
  const auto kind = cfg_.at("surfaces").get<std::string>();
  if (kind == "none") return;
  fs::create_directories(dir_ / "surfaces");
  const fs::path path = dir_ / "surfaces" / fmt::format("{}_{:05d}.{}", object, frame, kind);
  if (z_up_) {
    mesh::SurfaceMesh turned = surface;
    for (auto& x : turned.vertices) x = z_up(x);
    std::vector<Eigen::Vector3d> v = velocity;
    for (auto& x : v) x = z_up(x);
    if (kind == "ply") mesh::io::write_ply(path, turned, v);
    else write_obj(path, turned);
  } else if (kind == "ply") {
    mesh::io::write_ply(path, surface, velocity);
  } else {
    write_obj(path, surface);
  }
  bytes_.surfaces += fs::file_size(path);
}

double Output::voxel_size(double mean_edge_length) {
  if (voxel_size_ == 0) voxel_size_ = 0.5 * mean_edge_length;
  return voxel_size_;
}

Output::SurfaceScale Output::liquid_surface_scale(double cut_edge) {
  const scene::Json surface = cfg_.value("liquid_surface", scene::Json::object());
  if (surface_scale_.voxel_size == 0 && cut_edge > 0) {  // the first frame with a cut tet fixes the defaults
    if (!surface.contains("smoothing")) surface_scale_.smoothing = cut_edge;
    surface_scale_.voxel_size = surface.value("voxel_size", 0.25 * (surface_scale_.smoothing > 0 ? surface_scale_.smoothing : cut_edge));
    if (!(surface_scale_.smoothing <= scene::kMaxSmoothingVoxels * surface_scale_.voxel_size))
      throw InputError(fmt::format("/export/liquid_surface/smoothing: {:.4g} m is more than {:g} voxels of {:.4g} m "
                                   "(/export/liquid_surface/voxel_size): raise voxel_size or lower smoothing",
                                   surface_scale_.smoothing, scene::kMaxSmoothingVoxels, surface_scale_.voxel_size));
  }
  return surface_scale_;
}

void Output::write_volumes(const std::string& object, int frame, fluid::VoxelSamples samples,
                           const mesh::SurfaceMesh* surface) {
  if (!volumes_) return;
  fs::create_directories(dir_ / "volumes");
  const fs::path path = dir_ / "volumes" / fmt::format("{}_{:05d}.vdb", object, frame);
  mesh::SurfaceMesh turned;
  if (z_up_) {
    for (auto& ijk : samples.index) ijk = Eigen::Vector3i(ijk.x(), -ijk.z(), ijk.y());
    for (auto& u : samples.velocity) u = Eigen::Vector3f(u.x(), -u.z(), u.y());
    if (surface) {
      turned = *surface;
      for (auto& x : turned.vertices) x = z_up(x);
      surface = &turned;
    }
  }
  bytes_.volumes += fluid::write_vdb(path, samples, surface);
}

void Output::begin_stats(const std::vector<std::string>& header) {
  stats_bytes_ = open_csv(stats_, dir_ / "stats.csv", header);
}
void Output::stats_row(const std::vector<double>& row) { append_row(stats_, stats_bytes_, row); }
void Output::begin_probes(const std::vector<std::string>& header) {
  probes_bytes_ = open_csv(probes_, dir_ / "probes.csv", header);
}
void Output::probes_row(const std::vector<double>& row) { append_row(probes_, probes_bytes_, row); }

Output::State Output::state() const {
  return {pvd_entries_, bytes_, voxel_size_, surface_scale_, stats_bytes_, probes_bytes_};
}

void Output::resume(const State& state, const std::vector<std::string>& header,
                    const std::vector<std::string>& probes_header) {
  pvd_entries_ = state.pvd_entries;
  pvds_.clear();
  for (const auto& [object, entries] : pvd_entries_) {
    auto& pvd = pvds_[object];
    pvd = std::make_unique<mesh::io::PvdCollection>(dir_ / (object + ".pvd"));
    for (const auto& [time, file] : entries) pvd->add(time, file);  // the last add writes the whole list
  }
  bytes_ = state.bytes;
  voxel_size_ = state.voxel_size;
  surface_scale_ = state.surface_scale;
  stats_bytes_ = reopen_csv(stats_, dir_ / "stats.csv", header, state.stats_bytes);
  if (!probes_header.empty()) probes_bytes_ = reopen_csv(probes_, dir_ / "probes.csv", probes_header, state.probes_bytes);
}

}  // namespace tetfsi::run
