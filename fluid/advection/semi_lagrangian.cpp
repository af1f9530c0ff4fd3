#include "fluid/advection/semi_lagrangian.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

#include <tbb/parallel_for.h>

#include <atomic>
#include <optional>
#include <stdexcept>

namespace tetfsi::fluid {
namespace {

constexpr int kBlock = 256;  ///< samples per deterministic work block
int num_blocks(int n) { return (n + kBlock - 1) / kBlock; }

/// Per-tet fields packed as 5 doubles (velocity, smoke, temperature), at tets or at nodes.
using Packed = std::vector<Eigen::Matrix<double, 5, 1>>;

Packed pack(const FluidFields& f) {
  Packed p(f.velocity.size());
  for (size_t t = 0; t < p.size(); ++t) p[t] << f.velocity[t], f.smoke[t], f.temperature[t];
  return p;
}

/// Weighted node averages of packed tet values (the reconstruction; see header); the weights are
/// the tet volumes unless `weight` is given.
Packed to_nodes(const FluidMesh& m, const Packed& tet_values, const std::vector<double>* weight = nullptr) {
  return weighted_node_average(m, tet_values, weight);
}

Eigen::Matrix<double, 5, 1> interp(const FluidMesh& m, const Packed& nodal, const Location& l) {
  Eigen::Matrix<double, 5, 1> v = Eigen::Matrix<double, 5, 1>::Zero();
  for (int k = 0; k < 4; ++k) v += l.bary[k] * nodal[m.tets[l.tet][k]];
  return v;
}

/// Centroid-preserving, limited tet-wise linear reconstruction (AdvectionScheme::kLinear) in the
/// foot's tet, whose own value is `tet_value`.
Eigen::Matrix<double, 5, 1> interp_linear(const FluidMesh& m, const Eigen::Matrix<double, 5, 1>& tet_value,
                                          const Packed& nodal, const Location& l) {
  const auto& tet = m.tets[l.tet];
  Eigen::Matrix<double, 5, 1> v = tet_value, lo = v, hi = v;
  for (int k = 0; k < 4; ++k) {
    v += (l.bary[k] - 0.25) * nodal[tet[k]];
    lo = lo.cwiseMin(nodal[tet[k]]);
    hi = hi.cwiseMax(nodal[tet[k]]);
  }
  return v.cwiseMax(lo).cwiseMin(hi);
}

/// The packed value of tet t of `f` (pack() without the copy of every tet).
Eigen::Matrix<double, 5, 1> tet_value(const FluidFields& f, int t) {
  Eigen::Matrix<double, 5, 1> v;
  v << f.velocity[t], f.smoke[t], f.temperature[t];
  return v;
}

Eigen::Vector3d interp_velocity(const FluidMesh& m, const Packed& nodal, const Location& l) {
  return interp(m, nodal, l).head<3>();
}

/// Moves from `from` (inside, at `from_loc`) towards `to`; returns the location of `to` if inside,
/// else of the last inside point found by bisection on the segment. The walk to `to` starts at
/// `hint` (a tet near `to`; -1: from_loc's tet).
Location trace_to(const PointLocator& loc, const Eigen::Vector3d& from, const Location& from_loc,
                  const Eigen::Vector3d& to, int& clamped, bool* cut = nullptr, int hint = -1) {
  Location l = loc.locate(to, hint >= 0 ? hint : from_loc.tet);
  if (l.inside) return l;
  ++clamped;
  if (cut) *cut = true;
  Eigen::Vector3d a = from, b = to;
  Location la = from_loc;
  for (int it = 0; it < 12; ++it) {
    const Eigen::Vector3d mid = 0.5 * (a + b);
    Location lm = loc.locate(mid, la.tet);
    if (lm.inside) {
      a = mid;
      la = lm;
    } else {
      b = mid;
    }
  }
  return la;
}

/// RK2 (midpoint) foot of x0, traced for time h (negative: forward) through the velocity
/// reconstructed on `vel_mesh`, as a location in `vel_mesh`; the walk starts at `hint`, which
/// becomes the start's tet. Counts clamped traces and starts outside the fluid.
Location trace_foot(const FluidMesh& vel_mesh, const PointLocator& locator, const Packed& nodal,
                    const Eigen::Vector3d& x0, double h, int& hint, int& clamped, int& outside, bool& cut) {
  const Location l0 = locator.locate(x0, hint);
  hint = l0.tet;
  if (!l0.inside) {
    ++outside;
    return l0;
  }
  const Eigen::Vector3d xm = x0 - 0.5 * h * interp_velocity(vel_mesh, nodal, l0);
  const Location lm = trace_to(locator, x0, l0, xm, clamped);
  // The foot x0 - h v(xm) lies about h|v|/2 from the midpoint and h|v| from x0: walk from the
  // midpoint's tet (a third fewer walk steps); a cut trace still bisects the segment from x0.
  return trace_to(locator, x0, l0, x0 - h * interp_velocity(vel_mesh, nodal, lm), clamped, &cut, lm.tet);
}

template <class Point, class Start, class Visit>
void for_each_foot(const FluidMesh& vel_mesh, const PointLocator& locator, const Packed& nodal, int n,
                   const Point& point, const Start& start, double h, AdvectionReport& rep, const Visit& visit);

/// Calls visit(block, t, foot, cut) for the RK2 (midpoint) foot of the centroid of every tet t of
/// `targets`, traced for time h (negative: forward) through the velocity reconstructed on
/// `vel_mesh`, as a location in `vel_mesh`; cut: the final trace was cut at the fluid boundary.
/// Blocks of kBlock targets run in parallel, each in order (the walks, hence the feet, do not
/// depend on the thread count); visit may write to slot t or to its block's own storage.
template <class Visit>
void for_each_foot(const FluidMesh& vel_mesh, const PointLocator& locator, const Packed& nodal,
                   const FluidMesh& targets, double h, AdvectionReport& rep, const Visit& visit) {
  // When the target mesh is the velocity mesh moved (the same tets, as between two remeshes of a
  // coupled run), the centroid of target tet t lies in or next to its tet of the velocity mesh:
  // the walk starts there (one or two steps) instead of at the previous sample's tet.
  const std::vector<int> match = matching_tets(vel_mesh, targets);
  for_each_foot(
      vel_mesh, locator, nodal, targets.num_tets(), [&](int t) -> Eigen::Vector3d { return targets.centroid(t); },
      [&](int t) { return match.empty() ? -1 : match[t]; }, h, rep, visit);
}

/// for_each_foot for n samples at point(t), whose walks start at tet start(t) of vel_mesh (-1: at
/// the previous sample's tet in the block, or from the grid).
template <class Point, class Start, class Visit>
void for_each_foot(const FluidMesh& vel_mesh, const PointLocator& locator, const Packed& nodal, int n,
                   const Point& point, const Start& start, double h, AdvectionReport& rep, const Visit& visit) {
  std::atomic<int> clamped_total{0}, outside_total{0};
  tbb::parallel_for(0, num_blocks(n), [&](int b) {
    int hint = -1, clamped = 0, outside = 0;
    for (int t = b * kBlock; t < std::min(n, (b + 1) * kBlock); ++t) {
      if (const int s = start(t); s >= 0) hint = s;
      bool cut = false;
      const Location foot = trace_foot(vel_mesh, locator, nodal, point(t), h, hint, clamped, outside, cut);
      visit(b, t, foot, cut);
    }
    clamped_total += clamped;
    outside_total += outside;
  });
  rep.clamped += clamped_total;
  rep.outside_start += outside_total;
}

/// The feet of for_each_foot, one per target tet; `cut` (if given): 1 for the samples whose final
/// trace was cut at the fluid boundary.
std::vector<Location> trace_feet(const FluidMesh& vel_mesh, const PointLocator& locator, const Packed& nodal,
                                 const FluidMesh& targets, double h, AdvectionReport& rep,
                                 std::vector<char>* cut = nullptr) {
  if (cut) cut->assign(targets.num_tets(), 0);
  std::vector<Location> feet(targets.num_tets());
  for_each_foot(vel_mesh, locator, nodal, targets, h, rep, [&](int, int t, const Location& foot, bool foot_cut) {
    feet[t] = foot;
    if (cut && foot_cut) (*cut)[t] = 1;
  });
  return feet;
}

/// Boundary face (index into the old mesh's boundary_faces; face_of: (4 tet + local face, face),
/// sorted) through which a trace cut at `foot` left the fluid, -1 if not found (see
/// semi_lagrangian.hpp: nearest boundary face of the foot's tet, within 0.01).
int exit_face(const std::vector<std::pair<std::int64_t, int>>& face_of, const Location& foot) {
  int best = -1;
  double best_bary = 0.01;
  for (int k = 0; k < 4; ++k) {
    const std::pair<std::int64_t, int> key{4 * static_cast<std::int64_t>(foot.tet) + k, -1};
    const auto it = std::lower_bound(face_of.begin(), face_of.end(), key);
    const int f = it != face_of.end() && it->first == key.first ? it->second : -1;
    if (f >= 0 && foot.bary[k] <= best_bary) {
      best_bary = foot.bary[k];
      best = f;
    }
  }
  return best;
}

/// The prescribed velocity of inflow face f at the foot (which lies on it): the face's vertex
/// velocities weighted by the foot's barycentric coordinates of those vertices, renormalised.
Eigen::Vector3d inflow_at(const FluidMesh& old_mesh, const BoundaryExits& exits, int f, const Location& foot) {
  const BoundaryFace& bf = old_mesh.boundary_faces[f];
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  double weight = 0;
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 4; ++k)
      if (old_mesh.tets[foot.tet][k] == bf.nodes[a]) {
        const double w = std::max(foot.bary[k], 0.0);
        u += w * exits.inflow_velocity[f][a];
        weight += w;
      }
  return weight > 0 ? Eigen::Vector3d(u / weight)
                    : Eigen::Vector3d((exits.inflow_velocity[f][0] + exits.inflow_velocity[f][1] +
                                       exits.inflow_velocity[f][2]) / 3.0);
}

/// A sample whose final trace was cut at the fluid boundary: its tet and its foot.
struct CutFoot {
  int tet;
  Location foot;
};

/// The samples whose trace left through an open face (ExitRule::kOpen) drop their tangential
/// velocity; those that left through an inflow face (ExitRule::kInflow) take its velocity.
void apply_exits(const FluidMesh& old_mesh, const BoundaryExits& exits, const std::vector<CutFoot>& cut_feet,
                 TetVectors& velocity, AdvectionReport& rep) {
  if (cut_feet.empty()) return;
  // (4 tet + local face, boundary face), sorted: the boundary faces are few beside 4 per tet.
  std::vector<std::pair<std::int64_t, int>> face_of(old_mesh.boundary_faces.size());
  for (size_t f = 0; f < old_mesh.boundary_faces.size(); ++f) {
    const BoundaryFace& bf = old_mesh.boundary_faces[f];
    face_of[f] = {4 * static_cast<std::int64_t>(bf.tet) + bf.local_face, static_cast<int>(f)};
  }
  std::sort(face_of.begin(), face_of.end());
  for (const CutFoot& c : cut_feet) {
    const int f = exit_face(face_of, c.foot);
    if (f < 0 || exits.rule[f] == ExitRule::kClamp) continue;
    Eigen::Vector3d& u = velocity[c.tet];
    if (exits.rule[f] == ExitRule::kInflow) {
      u = inflow_at(old_mesh, exits, f, c.foot);
      ++rep.inflow_feet;
      continue;
    }
    const Eigen::Vector3d& n = old_mesh.boundary_faces[f].normal;
    const double un = u.dot(n);
    if (un < 0.0) {
      u = un * n;
      ++rep.backflow_feet;
    }
  }
}

/// Stores the packed value v as tet t of `f`.
void store(FluidFields& f, int t, const Eigen::Matrix<double, 5, 1>& v) {
  f.velocity[t] = v.head<3>();
  f.smoke[t] = v[3];
  f.temperature[t] = v[4];
}

Eigen::Vector3d position(const FluidMesh& m, const Location& l) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) x += l.bary[k] * m.nodes[m.tets[l.tet][k]];
  return x;
}

void check_advection_inputs(const FluidMesh& old_mesh, const FluidFields& old_fields, const BoundaryExits* exits,
                            const std::vector<double>* node_weight) {
  if (node_weight && static_cast<int>(node_weight->size()) != old_mesh.num_tets())
    throw std::invalid_argument("advect: node-average weights do not match the old mesh's tet count");
  if (exits && exits->rule.size() != old_mesh.boundary_faces.size())
    throw std::invalid_argument("advect: exit rules do not match the old mesh's boundary faces");
  if (static_cast<int>(old_fields.velocity.size()) != old_mesh.num_tets() ||
      old_fields.smoke.size() != old_mesh.num_tets() || old_fields.temperature.size() != old_mesh.num_tets())
    throw std::invalid_argument("advect: old fields do not match the old mesh's tet count");
}

/// Which traces were cut at the boundary matters only where some face is open or an inflow (apply_exits).
bool any_open_face(const BoundaryExits* exits) {
  return exits && std::any_of(exits->rule.begin(), exits->rule.end(), [](ExitRule r) { return r != ExitRule::kClamp; });
}

FluidFields fields_of_size(int n) {
  FluidFields f;
  f.velocity.resize(n);
  f.smoke.resize(n);
  f.temperature.resize(n);
  return f;
}

/// kSemiLagrangian and kLinear for n samples at point(t), whose walks start at start(t)
/// (for_each_foot), in one pass: each sample's foot is read as it is found (no array of feet or of
/// packed values: at a million tets they were 100 bytes per tet of the step's peak memory). The
/// cut feet, few, are kept per block for apply_exits, in the samples' order.
template <class Point, class Start>
FluidFields advect_samples(const FluidMesh& old_mesh, const FluidFields& old_fields, int n, const Point& point,
                           const Start& start, double h, AdvectionReport& rep, AdvectionScheme scheme,
                           const BoundaryExits* exits, const std::vector<double>* node_weight,
                           const PointLocator& old_locator) {
  const bool any_open = any_open_face(exits);
  // With node weights (a liquid), a foot in a tet that is not full of liquid reads the node
  // interpolant: the tet's own value is poorly constrained there (see node_weight).
  auto anchored = [&](int tet) { return !node_weight || (*node_weight)[tet] >= old_mesh.volume[tet]; };
  FluidFields advected = fields_of_size(n);
  const Packed f_nodal = weighted_node_average_of<Eigen::Matrix<double, 5, 1>>(
      old_mesh, [&](int t) { return tet_value(old_fields, t); }, node_weight);
  std::vector<std::vector<CutFoot>> cut_by_block(any_open ? num_blocks(n) : 0);
  for_each_foot(old_mesh, old_locator, f_nodal, n, point, start, h, rep,
                [&](int b, int t, const Location& foot, bool cut) {
                  store(advected, t,
                        scheme == AdvectionScheme::kLinear && anchored(foot.tet)
                            ? interp_linear(old_mesh, tet_value(old_fields, foot.tet), f_nodal, foot)
                            : interp(old_mesh, f_nodal, foot));
                  if (any_open && cut) cut_by_block[b].push_back({t, foot});
                });
  if (any_open) {
    std::vector<CutFoot> cut_feet;
    for (const auto& block : cut_by_block) cut_feet.insert(cut_feet.end(), block.begin(), block.end());
    apply_exits(old_mesh, *exits, cut_feet, advected.velocity, rep);
  }
  return advected;
}

/// kBfecc (see semi_lagrangian.hpp): the plain advection, its reverse onto the old mesh, and the
/// corrected advection with the limiter.
FluidFields advect_bfecc(const FluidMesh& old_mesh, const FluidFields& old_fields, const FluidMesh& new_mesh, double h,
                         AdvectionReport& rep, const BoundaryExits* exits, const std::vector<double>* node_weight,
                         const PointLocator& old_locator) {
  const bool any_open = any_open_face(exits);
  const int n = new_mesh.num_tets();
  FluidFields advected = fields_of_size(n);
  const Packed f = pack(old_fields);
  const Packed f_nodal = to_nodes(old_mesh, f, node_weight);
  std::vector<char> cut;
  const std::vector<Location> feet =
      trace_feet(old_mesh, old_locator, f_nodal, new_mesh, h, rep, any_open ? &cut : nullptr);
  Packed forward(n);
  tbb::parallel_for(0, n, [&](int t) { forward[t] = interp(old_mesh, f_nodal, feet[t]); });
  // Reverse step: trace the OLD centroids forward through the same old velocity, read f^ on the new mesh.
  AdvectionReport back_rep;
  const std::vector<Location> ahead = trace_feet(old_mesh, old_locator, f_nodal, old_mesh, -h, back_rep);
  const Packed forward_nodal = to_nodes(new_mesh, forward);
  const PointLocator new_locator(new_mesh);
  Packed corrected(old_mesh.num_tets());
  tbb::parallel_for(0, num_blocks(old_mesh.num_tets()), [&](int b) {
    int hint = -1;
    for (int t = b * kBlock; t < std::min(old_mesh.num_tets(), (b + 1) * kBlock); ++t) {
      const Location l = new_locator.locate(position(old_mesh, ahead[t]), hint);
      hint = l.tet;
      const auto back = interp(new_mesh, forward_nodal, l);  // clamped barycentric if outside
      corrected[t] = f[t] + 0.5 * (f[t] - back);
    }
  });
  const Packed corrected_nodal = to_nodes(old_mesh, corrected, node_weight);
  tbb::parallel_for(0, n, [&](int t) {
    const Eigen::Matrix<double, 5, 1> v = interp(old_mesh, corrected_nodal, feet[t]);
    Eigen::Matrix<double, 5, 1> lo = f_nodal[old_mesh.tets[feet[t].tet][0]], hi = lo;
    for (int k = 1; k < 4; ++k) {
      lo = lo.cwiseMin(f_nodal[old_mesh.tets[feet[t].tet][k]]);
      hi = hi.cwiseMax(f_nodal[old_mesh.tets[feet[t].tet][k]]);
    }
    // Limiter (Selle et al. 2008): revert to the plain value where the correction overshoots.
    for (int c = 0; c < 5; ++c)
      if (v[c] >= lo[c] && v[c] <= hi[c]) forward[t][c] = v[c];
    store(advected, t, forward[t]);
  });
  if (any_open) {
    std::vector<CutFoot> cut_feet;
    for (int t = 0; t < n; ++t)
      if (cut[t]) cut_feet.push_back({t, feet[t]});
    apply_exits(old_mesh, *exits, cut_feet, advected.velocity, rep);
  }
  return advected;
}

}  // namespace

FluidFields advect(const FluidMesh& old_mesh, const FluidFields& old_fields, const FluidMesh& new_mesh, double h,
                   AdvectionReport* report, AdvectionScheme scheme, const BoundaryExits* exits,
                   const std::vector<double>* node_weight, const PointLocator* given_locator) {
  check_advection_inputs(old_mesh, old_fields, exits, node_weight);
  AdvectionReport rep;
  std::optional<PointLocator> own_locator;
  if (!given_locator) own_locator.emplace(old_mesh);
  const PointLocator& old_locator = given_locator ? *given_locator : *own_locator;
  FluidFields advected;
  if (scheme == AdvectionScheme::kBfecc) {
    advected = advect_bfecc(old_mesh, old_fields, new_mesh, h, rep, exits, node_weight, old_locator);
  } else {
    // When the new mesh is the old one moved (the same tets, as between two remeshes of a coupled
    // run), the centroid of new tet t lies in or next to its old tet: the walk starts there.
    const std::vector<int> match = matching_tets(old_mesh, new_mesh);
    advected = advect_samples(
        old_mesh, old_fields, new_mesh.num_tets(),
        [&](int t) -> Eigen::Vector3d { return new_mesh.centroid(t); },
        [&](int t) { return match.empty() ? -1 : match[t]; }, h, rep, scheme, exits, node_weight, old_locator);
  }
  if (report) *report = rep;
  return advected;
}

FluidFields advect_onto_moved(const FluidMesh& old_mesh, const FluidFields& old_fields,
                              const std::vector<Eigen::Vector3d>& moved_nodes, double h, AdvectionReport* report,
                              AdvectionScheme scheme, const BoundaryExits* exits,
                              const std::vector<double>* node_weight, const PointLocator* given_locator) {
  if (scheme == AdvectionScheme::kBfecc)
    throw std::invalid_argument("advect_onto_moved: BFECC needs the new mesh (advect())");
  if (static_cast<int>(moved_nodes.size()) != old_mesh.num_nodes())
    throw std::invalid_argument("advect_onto_moved: one moved position per node of the old mesh expected");
  check_advection_inputs(old_mesh, old_fields, exits, node_weight);
  AdvectionReport rep;
  std::optional<PointLocator> own_locator;
  if (!given_locator) own_locator.emplace(old_mesh);
  const PointLocator& old_locator = given_locator ? *given_locator : *own_locator;
  FluidFields advected = advect_samples(
      old_mesh, old_fields, old_mesh.num_tets(), [&](int t) { return centroid_at(old_mesh, moved_nodes, t); },
      [](int t) { return t; }, h, rep, scheme, exits, node_weight, old_locator);
  if (report) *report = rep;
  return advected;
}

}  // namespace tetfsi::fluid
