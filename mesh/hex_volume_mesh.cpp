#include "mesh/hex_volume_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "mesh/cell_checks.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/io/msh_reader.hpp"
#include "mesh/volume_mesh.hpp"

namespace tetfsi::mesh {
namespace {

std::string num(double x) {
  std::ostringstream s;
  s.precision(4);
  s << x;
  return s.str();
}
std::string str(int i) { return std::to_string(i); }

/// Edges of a VTK hexahedron (bottom, top, vertical).
constexpr int kHexEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                  {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

double longest_edge(const HexMesh& m, const std::array<int, 8>& h) {
  double l = 0;
  for (const auto& e : kHexEdges) l = std::max(l, (m.vertices[h[e[0]]] - m.vertices[h[e[1]]]).norm());
  return l;
}

/// The Gauss point g of the 2 x 2 x 2 rule, (+-1/sqrt 3)^3 in the corner order of VTK.
Eigen::Vector3d gauss_point(int g) {
  static constexpr int s[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                  {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  return Eigen::Vector3d(s[g][0], s[g][1], s[g][2]) / std::sqrt(3.0);
}

std::string point_name(int g) {
  const Eigen::Vector3d xi = gauss_point(g);
  return "Gauss point " + str(g) + " (xi, eta, zeta) = (" + num(xi.x()) + ", " + num(xi.y()) + ", " + num(xi.z()) + ")";
}

/// +1 if det(dX/dxi) is positive at all 8 Gauss points, -1 if negative at all.
/// @throws MeshError naming the hex and Gauss point if one is degenerate or the signs differ
int orientation(const HexMesh& m, int e, const std::string& label) {
  const auto& h = m.hexes[e];
  const double l = longest_edge(m, h), floor = kDegenerateHexJacobian * l * l * l / 8;
  std::array<Eigen::Vector3d, 8> x;
  for (int a = 0; a < 8; ++a) x[a] = m.vertices[h[a]];
  std::array<double, 8> J{};
  int positive = 0;
  for (int g = 0; g < 8; ++g) {
    J[g] = hex_jacobian_determinant(x, gauss_point(g));
    if (!(std::fabs(J[g]) > floor))
      throw MeshError(label + ": hex " + str(e) + " is degenerate at its " + point_name(g) + ": det(dX/dxi) " +
                      num(J[g]) + " m^3 for a longest edge of " + num(l) + " m");
    positive += J[g] > 0;
  }
  if (positive == 8) return 1;
  if (positive == 0) return -1;
  const bool few = positive >= 4;  // name a point of the minority sign
  const int g = static_cast<int>(std::find_if(J.begin(), J.end(), [&](double j) { return few ? j < 0 : j > 0; }) - J.begin());
  throw MeshError(label + ": hex " + str(e) + " is inverted or folded at its " + point_name(g) + ": det(dX/dxi) " +
                  num(J[g]) + " m^3, while " + str(few ? positive : 8 - positive) +
                  " of its 8 Gauss points have the opposite sign (the element turns inside out)");
}

/// Refuses two nodes closer than `tol` (every node is used by a hex at this point).
void check_duplicate_nodes(const HexMesh& m, double tol, const std::string& label) {
  std::vector<int> order(m.vertices.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return m.vertices[a].x() < m.vertices[b].x(); });
  for (std::size_t i = 0; i < order.size(); ++i)
    for (std::size_t j = i + 1; j < order.size() && m.vertices[order[j]].x() - m.vertices[order[i]].x() <= tol; ++j)
      if ((m.vertices[order[j]] - m.vertices[order[i]]).norm() <= tol) {
        const int a = std::min(order[i], order[j]), b = std::max(order[i], order[j]);
        const Eigen::Vector3d& x = m.vertices[a];
        throw MeshError(label + ": nodes " + str(a) + " and " + str(b) + " are duplicates (both at [" + num(x.x()) + ", " +
                        num(x.y()) + ", " + num(x.z()) + "] m): the hexes on either side are not joined; merge them");
      }
}

}  // namespace

HexMesh read_hex_volume_mesh(const std::string& path) {
  if (volume_mesh_extension(path) == ".msh") return as_mesh_error([&] { return io::read_msh_hexes(path); });
  HexMesh m;
  for (const auto& c : read_vtu_cells(path, true, m.vertices)) m.hexes.push_back({c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]});
  return m;
}

void check_hex_volume_mesh(HexMesh& m, const std::string& label, std::vector<std::string>& warnings) {
  cells::check_cells_and_nodes(m.vertices, m.hexes, label, "hex", "hexahedra");
  std::vector<bool> negative(m.hexes.size());
  for (int e = 0; e < m.num_hexes(); ++e) negative[e] = orientation(m, e, label) < 0;
  if (cells::all_negative(negative, label, "hex", "a tangled mesh, or hexes numbered mirror-wise")) {
    for (auto& h : m.hexes) h = {h[4], h[5], h[6], h[7], h[0], h[1], h[2], h[3]};
    warnings.push_back(label + ": every hex was negatively oriented (mirrored node numbering); reordered to positive "
                               "orientation (bottom and top faces swapped)");
  }
  if (const int dropped = cells::drop_unused_nodes(m.vertices, m.hexes))
    warnings.push_back(label + ": " + std::to_string(dropped) + " node(s) used by no hex were dropped");
  Eigen::Vector3d lo = m.vertices[0], hi = lo;
  for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  check_duplicate_nodes(m, 1e-9 * (hi - lo).norm(), label);
  cells::check_faces_and_pieces(m.hexes, kHexFaces, label, "hex");
}

HexMesh import_hex_volume_mesh(const std::string& path, const Placement& placement, std::vector<std::string>& warnings) {
  HexMesh m = read_hex_volume_mesh(path);
  apply_placement(m.vertices, placement);
  check_hex_volume_mesh(m, path, warnings);
  return m;
}

}  // namespace tetfsi::mesh
