#include "fluid/viscosity/viscous_boundary.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tetfsi::fluid {

WallCondition parse_wall_condition(const std::string& name) {
  if (name == "no_slip") return WallCondition::kNoSlip;
  if (name == "slip") return WallCondition::kSlip;
  throw std::invalid_argument("unknown wall condition '" + name + "' (expected no_slip or slip)");
}

namespace {

/// True if face `bf` faces across the thinnest extent of the patch's region (its normal within 60
/// degrees of that axis): a moving lid's region, thin across the lid, also holds the centroids of
/// the neighbouring walls' faces along its rim, which must not slide with it.
bool faces_across(const BoundaryPatch& patch, const BoundaryFace& bf) {
  int thin = 0;
  (patch.region.hi - patch.region.lo).minCoeff(&thin);
  return std::abs(bf.normal[thin]) > 0.5;
}

}  // namespace

ViscousNodes viscous_nodes(const FluidMesh& mesh, const ClassifiedBoundary& cb, const BoundaryConditions& bc,
                           WallCondition walls) {
  ViscousNodes out;
  out.fixed.assign(mesh.num_nodes(), 0);
  out.velocity.assign(mesh.num_nodes(), Eigen::Vector3d::Zero());
  // Priority by pass: later passes overwrite (wall < moving wall < inflow < interface).
  enum Pass { kRestingWall, kMovingWall, kInflowPatch, kSolid };
  for (int pass = kRestingWall; pass <= kSolid; ++pass)
    for (std::size_t f = 0; f < mesh.boundary_faces.size(); ++f) {
      const BoundaryFace& bf = mesh.boundary_faces[f];
      const FaceKind kind = cb.face_kind[f];
      const BoundaryPatch* patch = cb.face_patch[f] >= 0 ? &bc.patches[cb.face_patch[f]] : nullptr;
      const bool moving = kind == FaceKind::kWall && patch && patch->velocity.squaredNorm() > 0 && faces_across(*patch, bf);
      const bool slip = walls == WallCondition::kSlip || (patch && patch->slip);
      const bool take = (pass == kRestingWall && kind == FaceKind::kWall && !moving && !slip) ||
                        (pass == kMovingWall && moving) || (pass == kInflowPatch && kind == FaceKind::kInflow) ||
                        (pass == kSolid && kind == FaceKind::kInterface && walls == WallCondition::kNoSlip);
      if (!take) continue;
      for (int node : bf.nodes) {
        Eigen::Vector3d v = Eigen::Vector3d::Zero();
        if (pass == kMovingWall || pass == kInflowPatch)
          v = patch->velocity_field ? patch->velocity_field(mesh.nodes[node]) : patch->velocity;
        if (pass == kSolid && !bc.solid_vertex_velocity.empty())
          v = bc.solid_vertex_velocity[mesh.node_to_mesh_vertex[node]];
        else if (pass == kSolid && !bc.no_slip_velocity.empty())
          v = bc.no_slip_velocity.at(mesh.node_to_mesh_vertex[node]);
        out.fixed[node] = 1;
        out.velocity[node] = v;
      }
    }
  return out;
}

}  // namespace tetfsi::fluid
