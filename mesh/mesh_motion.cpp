#include "mesh/mesh_motion.hpp"

#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>

#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/remesh_region.hpp"   // vertex_kinds

namespace tetfsi::mesh {
namespace {

/// Gradients of the four P1 basis functions of a tet (rows), and its volume.
Eigen::Matrix<double, 4, 3> p1_gradients(const std::array<Eigen::Vector3d, 4>& x, double& volume) {
  Eigen::Matrix3d D;
  for (int k = 0; k < 3; ++k) D.col(k) = x[k + 1] - x[0];
  volume = D.determinant() / 6.0;
  const Eigen::Matrix3d Dinv_t = D.inverse().transpose();  // columns: gradients of φ1, φ2, φ3
  Eigen::Matrix<double, 4, 3> g;
  for (int k = 0; k < 3; ++k) g.row(k + 1) = Dinv_t.col(k).transpose();
  g.row(0) = -(g.row(1) + g.row(2) + g.row(3));
  return g;
}

}  // namespace

std::vector<Eigen::Vector3d> move_with_solids(const TetMesh& mesh, const std::vector<Eigen::Vector3d>& solid_positions,
                                              const MeshMotionOptions& options) {
  const int n = mesh.num_vertices();
  if (static_cast<int>(solid_positions.size()) != n)
    throw MeshError("mesh motion: expected " + std::to_string(n) + " positions, got " +
                    std::to_string(solid_positions.size()));
  const std::vector<int> kind = vertex_kinds(mesh);  // 0 free, 1 solid (prescribed), 2 boundary (fixed)
  std::vector<int> unknown(n, -1);
  int m = 0;
  for (int v = 0; v < n; ++v)
    if (kind[v] == 0) unknown[v] = m++;
  std::vector<Eigen::Vector3d> moved = mesh.vertices;
  bool still = true;
  for (int v = 0; v < n; ++v)
    if (kind[v] == 1) {
      moved[v] = solid_positions[v];
      still = still && moved[v] == mesh.vertices[v];
    }
  if (m == 0 || still) return moved;

  double v_max = 0;
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mesh.subdomain[t] == kFluidSubdomain) v_max = std::max(v_max, signed_volume(mesh, t));
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(16 * mesh.tets.size());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 3);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (mesh.subdomain[t] != kFluidSubdomain) continue;
    const auto& tet = mesh.tets[t];
    double volume = 0;
    const auto g = p1_gradients({mesh.vertices[tet[0]], mesh.vertices[tet[1]], mesh.vertices[tet[2]],
                                 mesh.vertices[tet[3]]},
                                volume);
    if (!(volume > 0)) throw MeshError("mesh motion: fluid tet " + std::to_string(t) + " is flat or inverted");
    const double s = std::pow(v_max / volume, options.stiffening_exponent) * volume;
    const Eigen::Matrix4d k = s * g * g.transpose();
    for (int i = 0; i < 4; ++i) {
      const int a = unknown[tet[i]];
      if (a < 0) continue;
      for (int j = 0; j < 4; ++j) {
        const int b = unknown[tet[j]];
        if (b >= 0)
          triplets.emplace_back(a, b, k(i, j));
        else
          rhs.row(a) -= k(i, j) * (moved[tet[j]] - mesh.vertices[tet[j]]).transpose();
      }
    }
  }
  Eigen::SparseMatrix<double> K(m, m);
  K.setFromTriplets(triplets.begin(), triplets.end());
  // CG with a diagonal preconditioner: K is SPD and the tolerance is relative to the right-hand
  // side (the prescribed motion), so a rigid-body step converges to round-off.
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  cg.setTolerance(options.tolerance);
  cg.setMaxIterations(std::max(1000, 4 * m));
  cg.compute(K);
  for (int c = 0; c < 3; ++c) {
    if (rhs.col(c).norm() == 0) continue;
    const Eigen::VectorXd d = cg.solve(rhs.col(c));
    if (cg.info() != Eigen::Success) throw MeshError("mesh motion: the stiffened Laplacian did not converge");
    for (int v = 0; v < n; ++v)
      if (unknown[v] >= 0) moved[v][c] += d[unknown[v]];
  }
  return moved;
}

}  // namespace tetfsi::mesh
