#include "fluid/operators/fluid_mesh.hpp"

#include <tbb/parallel_sort.h>

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace tetfsi::fluid {
namespace {

/// One face of a tet, keyed by its sorted vertex triple (TetMesh vertex ids).
struct FaceRecord {
  std::array<int, 3> key;
  int mesh_tet;
  int local_face;
};

/// Local vertices of the face opposite local vertex k, ordered so that the right-hand normal points
/// out of a positively oriented tet.
constexpr int kFaceVertices[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

/// Volumes, centroids and hat-function gradients of every fluid tet from fm.nodes: with
/// E = [x1-x0, x2-x0, x3-x0], the rows of E^-1 are grad(phi_1..3) and grad(phi_0) = -sum of the
/// others (partition of unity). Throws on a tet of non-positive volume.
void compute_tet_geometry(FluidMesh& fm) {
  const int nf = fm.num_tets();
  fm.volume.resize(nf);
  fm.grad.resize(nf);
  fm.centroids.resize(nf);
  for (int t = 0; t < nf; ++t) {
    const auto& v = fm.tets[t];
    fm.centroids[t] = 0.25 * (fm.nodes[v[0]] + fm.nodes[v[1]] + fm.nodes[v[2]] + fm.nodes[v[3]]);
    Eigen::Matrix3d e;
    e.col(0) = fm.nodes[v[1]] - fm.nodes[v[0]];
    e.col(1) = fm.nodes[v[2]] - fm.nodes[v[0]];
    e.col(2) = fm.nodes[v[3]] - fm.nodes[v[0]];
    const double det = e.determinant();
    if (!(det > 0.0))
      throw std::invalid_argument("fluid mesh: fluid tet " + std::to_string(fm.tet_to_mesh_tet[t]) +
                                  " has non-positive volume " + std::to_string(det / 6.0));
    fm.volume[t] = det / 6.0;
    const Eigen::Matrix3d inv = e.inverse();
    fm.grad[t][1] = inv.row(0).transpose();
    fm.grad[t][2] = inv.row(1).transpose();
    fm.grad[t][3] = inv.row(2).transpose();
    fm.grad[t][0] = -(fm.grad[t][1] + fm.grad[t][2] + fm.grad[t][3]);
  }
}

/// Area and unit outward normal of a boundary face from its nodes' positions.
void set_face_geometry(const std::vector<Eigen::Vector3d>& nodes, BoundaryFace& f) {
  const Eigen::Vector3d n = (nodes[f.nodes[1]] - nodes[f.nodes[0]]).cross(nodes[f.nodes[2]] - nodes[f.nodes[0]]);
  f.area = 0.5 * n.norm();
  f.normal = n.normalized();
}

/// Lumped node volumes sum_t V_t / 4, summed in tet order.
void compute_dual_volumes(FluidMesh& fm) {
  fm.dual_volume.assign(fm.num_nodes(), 0.0);
  for (int t = 0; t < fm.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) fm.dual_volume[fm.tets[t][k]] += 0.25 * fm.volume[t];
}

}  // namespace

double FluidMesh::mean_edge_length() const {
  double sum = 0.0;
  for (const auto& v : tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) sum += (nodes[v[a]] - nodes[v[b]]).norm();
  return tets.empty() ? 0.0 : sum / (6.0 * static_cast<double>(tets.size()));
}

FluidMesh build_fluid_mesh(const mesh::TetMesh& mesh) {
  const int nv = mesh.num_vertices();
  const int nt = mesh.num_tets();
  if (!mesh.subdomain.empty() && static_cast<int>(mesh.subdomain.size()) != nt)
    throw std::invalid_argument("build_fluid_mesh: subdomain has " + std::to_string(mesh.subdomain.size()) +
                                " labels for " + std::to_string(nt) + " tets");
  auto is_fluid = [&](int t) { return mesh.subdomain.empty() || mesh.subdomain[t] == mesh::kFluidSubdomain; };

  FluidMesh fm;
  fm.mesh_vertex_to_node.assign(nv, -1);
  std::vector<int> mesh_tet_to_fluid(nt, -1);
  for (int t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k)
      if (mesh.tets[t][k] < 0 || mesh.tets[t][k] >= nv)
        throw std::invalid_argument("build_fluid_mesh: tet " + std::to_string(t) + " has vertex index " +
                                    std::to_string(mesh.tets[t][k]) + " out of range");
    if (!is_fluid(t)) continue;
    mesh_tet_to_fluid[t] = static_cast<int>(fm.tets.size());
    std::array<int, 4> local{};
    for (int k = 0; k < 4; ++k) {
      int& node = fm.mesh_vertex_to_node[mesh.tets[t][k]];
      if (node < 0) {
        node = static_cast<int>(fm.nodes.size());
        fm.nodes.push_back(mesh.vertices[mesh.tets[t][k]]);
        fm.node_to_mesh_vertex.push_back(mesh.tets[t][k]);
      }
      local[k] = node;
    }
    fm.tets.push_back(local);
    fm.tet_to_mesh_tet.push_back(t);
  }
  if (fm.tets.empty()) throw std::invalid_argument("build_fluid_mesh: the mesh has no fluid tet (label 1)");

  compute_tet_geometry(fm);
  const int nf = fm.num_tets();

  // Face matching over ALL tets (so that faces shared with a solid tet know the solid's label).
  std::vector<FaceRecord> faces;
  faces.reserve(4 * static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> key{mesh.tets[t][kFaceVertices[k][0]], mesh.tets[t][kFaceVertices[k][1]],
                             mesh.tets[t][kFaceVertices[k][2]]};
      std::sort(key.begin(), key.end());
      faces.push_back({key, t, k});
    }
  // Keys are distinct (face, tet) pairs, so the order is total and the parallel sort deterministic.
  tbb::parallel_sort(faces.begin(), faces.end(), [](const FaceRecord& a, const FaceRecord& b) {
    return a.key != b.key ? a.key < b.key : a.mesh_tet < b.mesh_tet;
  });
  fm.neighbor.assign(nf, {-1, -1, -1, -1});
  auto add_boundary = [&](const FaceRecord& f, int other_label) {
    const int t = mesh_tet_to_fluid[f.mesh_tet];
    BoundaryFace bf;
    bf.tet = t;
    bf.local_face = f.local_face;
    for (int a = 0; a < 3; ++a) bf.nodes[a] = fm.tets[t][kFaceVertices[f.local_face][a]];
    set_face_geometry(fm.nodes, bf);
    bf.other_subdomain = other_label;
    fm.boundary_faces.push_back(bf);
  };
  for (size_t i = 0; i < faces.size();) {
    size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i > 2)
      throw std::invalid_argument("build_fluid_mesh: face shared by more than two tets (non-manifold mesh)");
    if (j - i == 2) {
      const FaceRecord& a = faces[i];
      const FaceRecord& b = faces[i + 1];
      const int fa = mesh_tet_to_fluid[a.mesh_tet], fb = mesh_tet_to_fluid[b.mesh_tet];
      if (fa >= 0 && fb >= 0) {
        fm.neighbor[fa][a.local_face] = fb;
        fm.neighbor[fb][b.local_face] = fa;
      } else if (fa >= 0) {
        add_boundary(a, mesh.subdomain[b.mesh_tet]);
      } else if (fb >= 0) {
        add_boundary(b, mesh.subdomain[a.mesh_tet]);
      }
    } else if (mesh_tet_to_fluid[faces[i].mesh_tet] >= 0) {
      add_boundary(faces[i], 0);
    }
    i = j;
  }

  fm.node_tets.assign(fm.num_nodes(), {});
  for (int t = 0; t < nf; ++t)
    for (int k = 0; k < 4; ++k) fm.node_tets[fm.tets[t][k]].push_back(t);
  compute_dual_volumes(fm);
  return fm;
}

void update_fluid_mesh_geometry(const mesh::TetMesh& mesh, FluidMesh& fm) {
  for (int i = 0; i < fm.num_nodes(); ++i) fm.nodes[i] = mesh.vertices[fm.node_to_mesh_vertex[i]];
  compute_tet_geometry(fm);
  for (BoundaryFace& f : fm.boundary_faces) set_face_geometry(fm.nodes, f);
  compute_dual_volumes(fm);
}

}  // namespace tetfsi::fluid
