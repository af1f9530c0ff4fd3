#include "apps/run/output.hpp"

#include <fmt/format.h>

#include "apps/run/errors.hpp"
#include "mesh/io/atomic_file.hpp"
#include "mesh/io/ply_writer.hpp"

namespace tetfsi::run {
namespace fs = std::filesystem;
namespace {

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
  for (std::size_t i = 0; i < row.size(); ++i) line += fmt::format("{}{:.17g}", i ? "," : "", row[i]);
  return line + "\n";
}

Output::Output(fs::path dir, scene::Json export_cfg) : dir_(std::move(dir)), cfg_(std::move(export_cfg)) {
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
  mesh::io::write_vtu(dir_ / rel, grid);
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
  if (kind == "ply") mesh::io::write_ply(path, surface, velocity);
  else write_obj(path, surface);
}

void Output::begin_stats(const std::vector<std::string>& header) { open_csv(stats_, dir_ / "stats.csv", header); }
void Output::stats_row(const std::vector<double>& row) { stats_ << csv_row(row) << std::flush; }
void Output::begin_probes(const std::vector<std::string>& header) { open_csv(probes_, dir_ / "probes.csv", header); }
void Output::probes_row(const std::vector<double>& row) { probes_ << csv_row(row) << std::flush; }

}  // namespace tetfsi::run
