#include "coupling/mesh_update.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "fluid/projection/amg_preconditioner.hpp"
#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/mesh_motion.hpp"
#include "mesh/quality.hpp"
#include "support/stopwatch.hpp"

namespace tetfsi::coupling {

MeshUpdatePolicy parse_mesh_update_policy(const std::string& name) {
  if (name == "move") return MeshUpdatePolicy::kMove;
  if (name == "remesh_when_needed") return MeshUpdatePolicy::kRemeshWhenNeeded;
  if (name == "remesh_every_step") return MeshUpdatePolicy::kRemeshEveryStep;
  throw std::invalid_argument("unknown mesh update policy '" + name +
                              "' (expected move, remesh_when_needed or remesh_every_step)");
}

std::string to_string(MeshUpdatePolicy policy) {
  switch (policy) {
    case MeshUpdatePolicy::kMove: return "move";
    case MeshUpdatePolicy::kRemeshWhenNeeded: return "remesh_when_needed";
    case MeshUpdatePolicy::kRemeshEveryStep: return "remesh_every_step";
  }
  return "?";
}

double fluid_edge_length_near_solids(const mesh::TetMesh& mesh) {
  std::vector<char> on_solid(mesh.num_vertices(), 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mesh.subdomain[t] != mesh::kFluidSubdomain)
      for (int v : mesh.tets[t]) on_solid[v] = 1;
  double sum = 0;
  long count = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (mesh.subdomain[t] != mesh::kFluidSubdomain) continue;
    const auto& tet = mesh.tets[t];
    if (!std::any_of(tet.begin(), tet.end(), [&](int v) { return on_solid[v] != 0; })) continue;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) sum += (mesh.vertices[tet[i]] - mesh.vertices[tet[j]]).norm(), ++count;
  }
  return count > 0 ? sum / count : mesh::mean_edge_length(mesh, mesh::kFluidSubdomain);
}

MeshUpdater::MeshUpdater(MeshUpdateOptions options) : options_(std::move(options)) {}
MeshUpdater::~MeshUpdater() = default;

MotionSolver parse_motion_solver(const std::string& name) {
  if (name == "auto") return MotionSolver::kAuto;
  if (name == "cholesky") return MotionSolver::kCholesky;
  if (name == "amg") return MotionSolver::kAmg;
  throw std::invalid_argument("unknown mesh motion solver '" + name + "' (expected auto, cholesky or amg)");
}

std::unique_ptr<mesh::MeshMotion> MeshUpdater::make_motion(const mesh::TetMesh& reference) const {
  mesh::MeshMotionOptions o = options_.motion;
  MotionSolver solver = options_.motion_solver;
  if (solver == MotionSolver::kAuto) {
    const auto fluid_tets =
        std::count(reference.subdomain.begin(), reference.subdomain.end(), mesh::kFluidSubdomain);
    solver = fluid_tets > options_.amg_motion_above_tets ? MotionSolver::kAmg : MotionSolver::kCholesky;
  }
  // Both move the mesh every step until the next remesh. The factorization is made at the second
  // step on a mesh (a mesh remeshed again at once never pays for it); CG with a BoomerAMG V-cycle
  // (its hierarchy set up once per mesh) solves every step without it and the first step with it.
  o.factorize = solver == MotionSolver::kCholesky;
  o.make_preconditioner = [](const Eigen::SparseMatrix<double>& K) -> mesh::MeshMotionOptions::Preconditioner {
    auto amg = std::make_shared<fluid::AmgPreconditioner>();
    amg->setup(K);
    return [amg](const Eigen::VectorXd& r, Eigen::VectorXd& z) { amg->apply(r, z); };
  };
  return std::make_unique<mesh::MeshMotion>(reference, o);
}

MeshUpdateResult update_mesh(const mesh::TetMesh& mesh, const std::vector<Eigen::Vector3d>& solid_positions,
                             const MeshUpdateOptions& options, double start_min_dihedral_deg) {
  return MeshUpdater(options).update(mesh, solid_positions, start_min_dihedral_deg);
}

MeshUpdateResult MeshUpdater::update(const mesh::TetMesh& mesh, const std::vector<Eigen::Vector3d>& solid_positions,
                                     double start_min_dihedral_deg) {
  const MeshUpdateOptions& options = options_;
  Stopwatch clock;
  if (!motion_ || motion_->num_vertices() != mesh.num_vertices()) motion_ = make_motion(mesh);
  MeshUpdateResult result;
  result.mesh = mesh;
  result.mesh.vertices = motion_->positions(solid_positions);
  result.moved_vertices = result.mesh.vertices;
  result.report.motion_seconds = clock.lap();
  result.report.motion_iterations = motion_->last_iterations();
  // One pass for the fluid's angles and flat/inverted count; the solid tets only need the latter.
  const mesh::AngleCheck fluid_quality = mesh::min_dihedral_check(result.mesh, mesh::kFluidSubdomain);
  int spoiled_solid = 0;
  for (int t = 0; t < result.mesh.num_tets(); ++t) {
    if (result.mesh.subdomain[t] == mesh::kFluidSubdomain) continue;
    const auto& v = result.mesh.tets[t];
    const auto& x = result.mesh.vertices;
    spoiled_solid += mesh::flat_or_inverted(x[v[0]], x[v[1]], x[v[2]], x[v[3]]) &&
               !mesh::flat_or_inverted(mesh.vertices[v[0]], mesh.vertices[v[1]], mesh.vertices[v[2]], mesh.vertices[v[3]]);
  }
  if (fluid_quality.flat_or_inverted > 0 || spoiled_solid > 0)
    throw mesh::MeshError(
        spoiled_solid > 0
            ? "the solid motion of this step inverts or flattens " + std::to_string(spoiled_solid) +
                  " of the solids' own tets (and " + std::to_string(fluid_quality.flat_or_inverted) +
                  " fluid tets); take a smaller time step, or a stiffer or finer solid"
            : "the solid motion of this step inverts or flattens " + std::to_string(fluid_quality.flat_or_inverted) +
                  " fluid tets even with the fluid vertices following; take a smaller time step");
  const double moved_fluid_min = fluid_quality.min_dihedral_deg;
  result.report.check_seconds = clock.lap();

  const auto keep_moved = [&] {
    result.old_index.resize(mesh.num_vertices());
    std::iota(result.old_index.begin(), result.old_index.end(), 0);
    result.report.min_dihedral_deg = moved_fluid_min;
  };
  const double threshold = std::min(options.remesh_below_deg, 0.5 * start_min_dihedral_deg);
  bool remesh = options.policy == MeshUpdatePolicy::kRemeshEveryStep;
  if (options.policy == MeshUpdatePolicy::kRemeshWhenNeeded) remesh = moved_fluid_min < threshold;
  // A refit: the fluid tets where the sizing field moved (SizeFieldRequest).
  const SizeFieldRequest request = std::move(size_request_);
  size_request_ = {};
  std::vector<char> misfit;
  if (request.size_then && request.size_now) {
    misfit = mesh::resized_tets(result.mesh, request.size_then, request.size_now, request.ratio, request.rings);
    if (std::find(misfit.begin(), misfit.end(), 1) == misfit.end()) {
      misfit.clear();
      result.report.size_field_fitted = true;
    }
  }
  const bool refit = !misfit.empty();
  if (!remesh && !refit) {
    keep_moved();
  } else {
    // Remesh the moved fluid (the motion is already done, so remesh_step's own motion is the
    // identity) only around the tets below the threshold (adaptive band), with the remesher's
    // fallback chain (more iterations, wider band, whole fluid) and sliver pass. A result that is
    // not better than the moved mesh (CGAL's isotropic remeshing can leave slivers where it meets
    // the frozen interface) is rejected: the moved mesh, which is valid, is kept and the report
    // says so.
    mesh::RemeshOptions opt = options.remesh;
    opt.motion = options.motion;
    opt.remesh_only_when_needed = options.policy == MeshUpdatePolicy::kRemeshWhenNeeded;
    opt.adaptive_band = opt.remesh_only_when_needed && opt.band > 0;
    opt.min_dihedral_deg = threshold;
    if (request.size_at) opt.size_at = request.size_at;
    if (refit) {  // the misfit tets, and the band around the solids if the policy remeshes now
      opt.remesh_only_when_needed = false;
      opt.adaptive_band = false;
      if (remesh) {
        const std::vector<char> near_solids = mesh::band_tets(result.mesh, opt.band);
        for (std::size_t t = 0; t < misfit.size(); ++t) misfit[t] |= near_solids[t];
      }
      opt.remesh_tets = std::move(misfit);
      opt.target_edge_length = request.far_edge;
    }
    mesh::RemeshResult r = mesh::remesh_step(result.mesh, result.mesh.vertices, opt);
    const mesh::QualityReport q = mesh::quality_report(r.mesh, mesh::kFluidSubdomain);
    const bool better = q.min_dihedral_deg > moved_fluid_min ||
                        (refit && q.min_dihedral_deg >= std::min(threshold, moved_fluid_min));
    if (r.report.remeshed && q.inverted + q.degenerate == 0 && better) {
      result.report.size_field_fitted = refit;
      result.mesh = std::move(r.mesh);
      result.old_index = std::move(r.old_index);
      result.report.remeshed = true;
      result.report.passes = r.report.passes;
      result.report.min_dihedral_deg = q.min_dihedral_deg;
      motion_.reset();  // the next step measures the motion from the new mesh
    } else {
      keep_moved();
      result.report.remesh_rejected = r.report.remeshed;
    }
  }
  result.report.seconds = result.report.motion_seconds + result.report.check_seconds + clock.seconds();
  return result;
}

}  // namespace tetfsi::coupling
