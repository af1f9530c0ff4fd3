#include "apps/run/output.hpp"

#include <cmath>
#include <regex>

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

void open_csv(std::ofstream& f, const fs::path& path, const std::vector<std::string>& header) {
  f.open(path, std::ios::trunc);
  if (!f) throw RunError("cannot create " + path.string());
  std::string line;
  for (const auto& h : header) line += (line.empty() ? "" : ",") + h;
  f << line << '\n' << std::flush;
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

OutputCleanup clean_output_folder(const fs::path& dir, bool earlier_run) {
  static const std::regex temporary(R"(.+\.tmp\.[0-9]+)");
  static const std::regex surface_frame(R"(.+_[0-9]{5}\.(ply|obj))");
  static const std::regex volume_frame(R"(.+_[0-9]{5}\.vdb)");
  OutputCleanup done;
  std::error_code ec;
  auto remove = [&](const fs::path& p, int& count) {
    if (fs::remove(p, ec)) ++count;
  };
  std::vector<fs::path> folders;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (e.is_directory(ec)) {
      folders.push_back(e.path());
    } else if (e.is_regular_file(ec)) {
      if (std::regex_match(name, temporary)) remove(e.path(), done.temporary_files);
      else if (earlier_run && (e.path().extension() == ".pvd" || name == "stats.csv" || name == "probes.csv"))
        remove(e.path(), done.earlier_run_files);
    }
  }
  for (const auto& folder : folders) {
    const std::string object = folder.filename().string();
    const std::regex frame(std::regex_replace(object, std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
                           R"(_[0-9]{5}\.vtu)");
    const int before = done.earlier_run_files;
    for (const auto& e : fs::directory_iterator(folder, ec)) {
      if (!e.is_regular_file(ec)) continue;
      const std::string name = e.path().filename().string();
      if (std::regex_match(name, temporary)) remove(e.path(), done.temporary_files);
      else if (earlier_run && (std::regex_match(name, frame) || (object == "surfaces" && std::regex_match(name, surface_frame)) ||
                               (object == "volumes" && std::regex_match(name, volume_frame))))
        remove(e.path(), done.earlier_run_files);
    }
    if (done.earlier_run_files > before && fs::is_empty(folder, ec)) fs::remove(folder, ec);
  }
  return done;
}

Output::Output(fs::path dir, scene::Json export_cfg)
    : dir_(std::move(dir)),
      cfg_(std::move(export_cfg)),
      compression_(cfg_.at("compression") == "none" ? mesh::io::VtuCompression::None : mesh::io::VtuCompression::Zlib),
      precision_(cfg_.at("precision") == "float64" ? mesh::io::VtuPrecision::Float64 : mesh::io::VtuPrecision::Float32),
      z_up_(cfg_.at("up_axis") == "z"),
      volumes_(cfg_.value("volumes", "none") == "vdb") {
  if (cfg_.contains("voxel_size")) voxel_size_ = cfg_["voxel_size"].get<double>();
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

void Output::begin_stats(const std::vector<std::string>& header) { open_csv(stats_, dir_ / "stats.csv", header); }
void Output::stats_row(const std::vector<double>& row) { stats_ << csv_row(row) << std::flush; }
void Output::begin_probes(const std::vector<std::string>& header) { open_csv(probes_, dir_ / "probes.csv", header); }
void Output::probes_row(const std::vector<double>& row) { probes_ << csv_row(row) << std::flush; }

}  // namespace tetfsi::run
