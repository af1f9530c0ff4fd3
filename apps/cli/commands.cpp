#include "apps/cli/commands.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <utility>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "apps/cli/validate_command.hpp"
#include "apps/run/driver.hpp"
#include "apps/run/errors.hpp"
#include "apps/run/output.hpp"
#include "apps/run/preflight.hpp"
#include "apps/run/solid_geometry.hpp"
#include "apps/scene/docs.hpp"
#include "apps/scene/scene.hpp"
#include "apps/version.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/quality.hpp"
#include "parallel/mpi_session.hpp"
#include "mesh/surface_checks.hpp"
#include "mesh/io/msh_writer.hpp"
#include "mesh/io/vtu_writer.hpp"

namespace tetfsi::cli {
namespace {

int mesh_command(const std::string& in, const std::string& out, double edge, double scale, double max_tets) {
  run::check_output_file(out, "output");
  std::vector<std::string> warnings;
  const auto surface = run::import_checked(in, scale, warnings);
  for (const auto& w : warnings) std::cerr << "warning: " << w << "\n";
  double area = 0;
  for (const auto& t : surface.triangles)
    area += 0.5 * (surface.vertices[t[1]] - surface.vertices[t[0]]).cross(surface.vertices[t[2]] - surface.vertices[t[0]]).norm();
  const double estimate = run::estimate_solid_tets(mesh::enclosed_volume(surface), area, edge);
  if (!(estimate <= max_tets))
    throw run::InputError(fmt::format("{}: the mesh would have about {:.3g} tets at --edge-length {:g} m, more than the "
                                      "limit of {:.3g} (--max-tets): raise --edge-length or --max-tets",
                                      in, estimate, edge, max_tets));
  mesh::MeshSizing sizing;
  sizing.edge_length = edge;
  mesh::TetMesh tets;
  try {
    tets = mesh::mesh_solid(surface, sizing);
  } catch (const mesh::MeshError& e) {
    throw run::InputError(fmt::format("{}: meshing failed: {}", in, e.what()));
  }
  if (std::filesystem::path(out).extension() == ".msh") mesh::io::write_msh(out, tets, mesh::io::MshVersion::k41);
  else mesh::io::write_vtu(out, mesh::io::make_grid(tets));
  std::cout << fmt::format("{}: {} vertices, {}\nwrote {}\n", in, tets.num_vertices(),
                           mesh::quality_report(tets).summary(), out);
  return 0;
}

/// `tetfsi report [ARGS]`: the speed-against-error report, scripts/report.py of the source tree
/// this binary was built from (TETFSI_SOURCE_DIR), run by the system Python (TETFSI_PYTHON) with
/// this binary and its build folder; ARGS (--quick, --out DIR, --cases a,b, ...) are passed on.
/// The process becomes the script's, so its exit code is the report's (1: a case outside its band).
int report_command(const std::vector<std::string>& args) {
  namespace fs = std::filesystem;
  const fs::path self = fs::read_symlink("/proc/self/exe");
  const fs::path script = fs::path(TETFSI_SOURCE_DIR) / "scripts" / "report.py";
  if (!fs::exists(script))
    throw run::InputError(fmt::format("report: {} is missing (the source tree this tetfsi was built from)",
                                      script.string()));
  std::vector<std::string> words = {TETFSI_PYTHON, script.string(), "--tetfsi", self.string(),
                                    "--build", self.parent_path().parent_path().string()};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  std::cout.flush();
  execv(TETFSI_PYTHON, argv.data());
  throw run::RunError(fmt::format("report: cannot start {}: {}", TETFSI_PYTHON, std::strerror(errno)));
}

}  // namespace

int dispatch(int argc, char** argv, const std::string& command_line) {
  CLI::App app{"tetfsi: fluids coupled two-way with deformable solids (Chentanez et al. 2006).\n"
               "Scenes are JSON files in SI units; start from data/scenes/ and docs/scene_format.md."};
  app.set_version_flag("--version", std::string("tetfsi ") + TETFSI_VERSION);
  app.require_subcommand(1);
  app.footer("Exit codes: 0 success, 2 invalid scene or input, 1 the run failed.\n"
             "Example: tetfsi run data/scenes/smoke_sheets.json --out out");

  run::RunOptions opt;
  double end_time = 0;
  int threads = 0;
  auto* run = app.add_subcommand("run", "Run a scene: writes .pvd/.vtu frames, surfaces, stats.csv, "
                                        "probes.csv and run.log into the output folder");
  run->add_option("scene", opt.scene_file, "Scene file (JSON)")->required();
  run->add_option("--out,-o", opt.out_dir, "Output folder; created if missing; the frames, .pvd and CSV files of an earlier run in it are removed, other files are kept")
      ->capture_default_str();
  auto* end_opt = run->add_option("--end-time", end_time, "Stop at this simulated time [s] (overrides the scene)");
  auto* thr_opt = run->add_option("--threads,-j", threads, "Worker threads; 0 = all cores (overrides the scene)");
  run->add_flag("--quiet,-q", opt.quiet, "No progress line");
  run->add_flag("--resume", opt.resume,
                "Continue the run in the output folder from its newest checkpoint (export.checkpoint_every); the "
                "scene may differ only in simulation.end_time / --end-time");
  double max_tets = 0;
  const std::string max_tets_help = cli::max_tets_help();
  auto* run_tets = run->add_option("--max-tets", max_tets, max_tets_help)->check(CLI::PositiveNumber);

  ValidateArgs validate_args;
  auto* val = add_validate_command(app, validate_args);

  std::string mesh_in, mesh_out;
  double edge = 0.1, scale = 1.0;
  auto* msh = app.add_subcommand("mesh", "Tetrahedralize a closed surface (OBJ, PLY, STL, glTF, FBX, OFF) "
                                         "and write a .vtu to look at in ParaView (or a Gmsh 4.1 .msh); both "
                                         "can be a solid's volume_mesh geometry");
  msh->add_option("input", mesh_in, "Closed surface file")->required()->check(CLI::ExistingFile);
  msh->add_option("output", mesh_out, "Output .vtu file (.msh: Gmsh 4.1 ASCII)")->required();
  msh->add_option("--edge-length", edge, "Target edge length [m]")->capture_default_str()->check(CLI::PositiveNumber);
  msh->add_option("--unit-scale", scale, "Metres per file unit (0.01 for cm)")->capture_default_str()->check(CLI::PositiveNumber);
  double mmax_tets = 0;
  auto* msh_tets = msh->add_option("--max-tets", mmax_tets, max_tets_help)->check(CLI::PositiveNumber);

  auto* sch = app.add_subcommand("schema", "Print the scene key reference (Markdown; docs/scene_format.md)");
  auto* rep = app.add_subcommand("report", "The speed-against-error report (scripts/report.py): every model's "
                                           "validation cases at several resolutions; options go to the script "
                                           "(--quick, --out DIR, --cases a,b; `tetfsi report --help` lists them)");
  rep->set_help_flag();  // --help goes to the script
  rep->allow_extras();

  // CLI11 says only "A subcommand is required" for a word that is not a command.
  bool known = argc < 2 || argv[1][0] == '-';
  for (const auto* sub : std::as_const(app).get_subcommands(nullptr)) known = known || sub->get_name() == argv[1];
  if (!known)
    throw run::InputError(fmt::format("unknown command '{}': the commands are run, validate, mesh, schema and report "
                                      "(tetfsi --help)", argv[1]));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  if (*run) {
    if (*end_opt) opt.end_time = end_time;
    if (*thr_opt) opt.threads = threads;
    if (*run_tets) opt.max_tets = max_tets;
    opt.command_line = command_line;
    run::run_scene(opt);
    if (!opt.quiet) std::cout << fmt::format("output in {}/ (open the .pvd files in ParaView; see run.log)\n",
                                             opt.out_dir.string());
    return 0;
  }
  if (*val) return validate(validate_args, parallel::num_processes());
  if (*msh) return mesh_command(mesh_in, mesh_out, edge, scale, *msh_tets ? mmax_tets : run::default_max_tets());
  if (*rep) return report_command(rep->remaining());
  if (*sch) {
    std::cout << scene::schema_markdown(scene::scene_schema());
    return 0;
  }
  return 2;
}

}  // namespace tetfsi::cli
