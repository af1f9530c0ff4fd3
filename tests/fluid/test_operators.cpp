// P1 operators: symmetry and sign of L, exactness of gradients, boundary flux quadrature.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "fluid/operators/boundary_flux.hpp"
#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "fluid_test_support.hpp"

namespace tetfsi::fluid {
namespace {

/// The sparse gradient matrix G (3T x N), row 3t + c = component c of the gradient on tet t,
/// assembled independently of gradient() and assemble_laplacian() to check them.
Eigen::SparseMatrix<double> gradient_matrix(const FluidMesh& mesh) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(12 * static_cast<size_t>(mesh.num_tets()));
  for (int t = 0; t < mesh.num_tets(); ++t)
    for (int k = 0; k < 4; ++k)
      for (int c = 0; c < 3; ++c) trip.emplace_back(3 * t + c, mesh.tets[t][k], mesh.grad[t][k][c]);
  Eigen::SparseMatrix<double> g(3 * mesh.num_tets(), mesh.num_nodes());
  g.setFromTriplets(trip.begin(), trip.end());
  return g;
}


const Eigen::Vector3d kLo(0, 0, 0), kHi(1, 0.75, 0.5);

FluidMesh jittered_box(int n, unsigned seed) {
  std::mt19937 rng(seed);
  const mesh::TetMesh base = mesh::structured_box(kLo, kHi, 4 * n, 3 * n, 2 * n);
  return build_fluid_mesh(testing::jittered(base, kLo, kHi, 0.25 / n, 0.1, rng));
}

TEST(FluidOperators, LaplacianSymmetricPositiveDiagonalConstantNullSpace) {
  const FluidMesh m = jittered_box(2, 1);
  const Eigen::SparseMatrix<double> l = assemble_laplacian(m);
  const Eigen::SparseMatrix<double> lt = l.transpose();
  EXPECT_LE((l - lt).norm(), 1e-14 * l.norm());
  for (int i = 0; i < l.rows(); ++i) EXPECT_GT(l.coeff(i, i), 0.0) << "node " << i;
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(l.rows());
  EXPECT_LE((l * ones).cwiseAbs().maxCoeff(), 1e-12 * l.diagonal().maxCoeff());
  // Positive semi-definite: p^T L p = sum_t V_t |grad p|^2 >= 0 for random p.
  std::mt19937 rng(5);
  std::normal_distribution<double> nd;
  for (int k = 0; k < 5; ++k) {
    Eigen::VectorXd p(l.rows());
    for (int i = 0; i < p.size(); ++i) p[i] = nd(rng);
    EXPECT_GT(p.dot(l * p), 0.0);
  }
}

TEST(FluidOperators, GradientOfLinearFieldIsExactAndLMatchesGTVG) {
  const FluidMesh m = jittered_box(1, 2);
  const Eigen::Vector3d a(0.3, -1.2, 2.5);
  Eigen::VectorXd p(m.num_nodes());
  for (int i = 0; i < m.num_nodes(); ++i) p[i] = a.dot(m.nodes[i]) + 4.0;
  for (const auto& g : gradient(m, p)) EXPECT_LE((g - a).norm(), 1e-12);
  const Eigen::SparseMatrix<double> g = gradient_matrix(m);
  Eigen::VectorXd v(3 * m.num_tets());
  for (int t = 0; t < m.num_tets(); ++t) v.segment<3>(3 * t).setConstant(m.volume[t]);
  const Eigen::SparseMatrix<double> gtvg = g.transpose() * v.asDiagonal() * g;
  EXPECT_LE((gtvg - assemble_laplacian(m)).norm(), 1e-12 * gtvg.norm());
  // G^T V u for a constant u is the boundary flux of u (divergence theorem on hat functions):
  // sum_t V_t grad(phi_i).u = int_dOmega phi_i u.n - int phi_i div u = boundary term.
  const Eigen::Vector3d u(1.0, -2.0, 0.5);
  const Eigen::VectorXd gtvu = gradient_transpose_volume(m, TetVectors(m.num_tets(), u));
  std::vector<int> faces(m.boundary_faces.size());
  std::vector<std::array<Eigen::Vector3d, 3>> vel(faces.size(), {u, u, u});
  for (size_t f = 0; f < faces.size(); ++f) faces[f] = static_cast<int>(f);
  const Eigen::VectorXd flux = boundary_flux(m, faces, vel);
  EXPECT_LE((gtvu - flux).cwiseAbs().maxCoeff(), 1e-13);
  // The matrix form of the flux agrees with the vector form.
  Eigen::VectorXd nodal(3 * m.num_nodes());
  for (int i = 0; i < m.num_nodes(); ++i) nodal.segment<3>(3 * i) = u;
  EXPECT_LE((boundary_flux_matrix(m, faces) * nodal - flux).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(FluidOperators, LaplacianOnUnknownsIsTheTripletSumBitForBit) {
  // assemble_laplacian(mesh, unknown, m, scale): every third node left out (open or pinned nodes),
  // the rest renumbered in node order; against a per-tet triplet sum in tet order (Eigen's
  // setFromTriplets sums duplicates in insertion order), then scaled: equal to the last bit.
  const FluidMesh m = jittered_box(2, 3);
  std::vector<int> unknown(m.num_nodes(), -1);
  int count = 0;
  for (int i = 0; i < m.num_nodes(); ++i)
    if (i % 3 != 1) unknown[i] = count++;
  std::vector<Eigen::Triplet<double>> trip;
  for (int t = 0; t < m.num_tets(); ++t)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        if (unknown[m.tets[t][a]] >= 0 && unknown[m.tets[t][b]] >= 0)
          trip.emplace_back(unknown[m.tets[t][a]], unknown[m.tets[t][b]], m.volume[t] * m.grad[t][a].dot(m.grad[t][b]));
  Eigen::SparseMatrix<double> expected(count, count);
  expected.setFromTriplets(trip.begin(), trip.end());
  const double scale = 0.0125 / 998.2;  // h / rho
  expected *= scale;
  const Eigen::SparseMatrix<double> l = assemble_laplacian(m, unknown, count, scale);
  ASSERT_EQ(l.nonZeros(), expected.nonZeros());
  ASSERT_TRUE(l.isCompressed());
  for (int c = 0; c < count; ++c) {
    Eigen::SparseMatrix<double>::InnerIterator it(l, c), ie(expected, c);
    for (; it && ie; ++it, ++ie) {
      ASSERT_EQ(it.row(), ie.row()) << "column " << c;
      ASSERT_EQ(it.value(), ie.value()) << "entry (" << it.row() << ", " << c << ")";
    }
    ASSERT_FALSE(it || ie) << "column " << c;
  }
}

TEST(FluidOperators, BoundaryFluxIsExactForLinearVelocity) {
  // Rotation about the box centre: u = w x (x - c) is linear and divergence-free, so the total
  // flux through the closed box surface is 0 and each face's flux is integrated exactly.
  const FluidMesh m = jittered_box(1, 3);
  const Eigen::Vector3d w(0.2, 1.0, -0.4), c = 0.5 * (kLo + kHi);
  std::vector<int> faces, top;
  std::vector<std::array<Eigen::Vector3d, 3>> vel, top_vel;
  for (size_t f = 0; f < m.boundary_faces.size(); ++f) {
    const auto& bf = m.boundary_faces[f];
    std::array<Eigen::Vector3d, 3> v;
    for (int a = 0; a < 3; ++a) v[a] = w.cross(m.nodes[bf.nodes[a]] - c);
    faces.push_back(static_cast<int>(f));
    vel.push_back(v);
    if (bf.normal.z() > 0.5) {
      top.push_back(static_cast<int>(f));
      top_vel.push_back(v);
    }
  }
  EXPECT_NEAR(boundary_flux(m, faces, vel).sum(), 0.0, 1e-14);
  // Top face z = 0.5: u.n = u_z = w_x (y - c_y) - w_y (x - c_x); the first moment
  // int x u_z dA = -w_y int_0^1 x (x - 0.5) dx * 0.75 = -w_y * 0.75 / 12, and sum_i x_i f_i = int x u_z
  // because x is in P1.
  const Eigen::VectorXd flux = boundary_flux(m, top, top_vel);
  double moment = 0.0;
  for (int i = 0; i < m.num_nodes(); ++i) moment += flux[i] * m.nodes[i].x();
  EXPECT_NEAR(moment, -w.y() * 0.75 / 12.0, 1e-13);
}

TEST(FluidOperators, RejectsInvertedTetAndMissingFluid) {
  mesh::TetMesh bad = mesh::structured_box(kLo, kHi, 1, 1, 1);
  std::swap(bad.tets[2][0], bad.tets[2][1]);
  EXPECT_THROW(build_fluid_mesh(bad), std::invalid_argument);
  mesh::TetMesh solid = mesh::structured_box(kLo, kHi, 1, 1, 1, mesh::solid_subdomain(0));
  EXPECT_THROW(build_fluid_mesh(solid), std::invalid_argument);
}

TEST(FluidOperators, TetsAreNumberedAlongASpaceFillingCurveWhateverTheMeshersOrder) {
  // The same box, its tets given in a random order: the fluid mesh numbers them along the Morton
  // curve of their centroids, so consecutive tets lie about a cell apart (measured 0.6 cell
  // edges on average here) where the shuffled order jumps across the box (about 11 edges).
  std::mt19937 rng(11);
  mesh::TetMesh box = mesh::structured_box(kLo, kHi, 16, 12, 8);
  std::shuffle(box.tets.begin(), box.tets.end(), rng);
  const double cell = (kHi - kLo).x() / 16;
  auto mean_step = [](const std::vector<Eigen::Vector3d>& c) {
    double sum = 0;
    for (std::size_t t = 1; t < c.size(); ++t) sum += (c[t] - c[t - 1]).norm();
    return sum / static_cast<double>(c.size() - 1);
  };
  std::vector<Eigen::Vector3d> given;
  for (const auto& tet : box.tets)
    given.push_back(0.25 * (box.vertices[tet[0]] + box.vertices[tet[1]] + box.vertices[tet[2]] + box.vertices[tet[3]]));
  const FluidMesh fm = build_fluid_mesh(box);
  std::vector<Eigen::Vector3d> built;
  for (int t = 0; t < fm.num_tets(); ++t) built.push_back(fm.centroid(t));
  std::printf("mean distance between consecutive tets: %.2f cells (given order %.2f)\n", mean_step(built) / cell,
              mean_step(given) / cell);
  EXPECT_LT(mean_step(built), 1.0 * cell);
  EXPECT_GT(mean_step(given), 5.0 * cell);
}

TEST(FluidOperators, MatchingTetsPairsMeshesOfOneTopologyAndNoOther) {
  // Two jittered copies of one box number their tets differently (each along its own centroids'
  // curve); matching_tets pairs the tets made from the same TetMesh tet. A mesh of other tets
  // (here: another resolution) has no match.
  std::mt19937 rng(5);
  const mesh::TetMesh base = mesh::structured_box(kLo, kHi, 6, 5, 4);
  const FluidMesh a = build_fluid_mesh(testing::jittered(base, kLo, kHi, 0.125, 0.1, rng));
  const FluidMesh b = build_fluid_mesh(testing::jittered(base, kLo, kHi, 0.125, 0.1, rng));
  const std::vector<int> match = matching_tets(a, b);
  ASSERT_EQ(static_cast<int>(match.size()), b.num_tets());
  int renumbered = 0;
  for (int t = 0; t < b.num_tets(); ++t) {
    ASSERT_EQ(a.tet_to_mesh_tet[match[t]], b.tet_to_mesh_tet[t]) << t;
    renumbered += match[t] != t;
  }
  std::printf("%d of %d tets numbered differently in the two copies\n", renumbered, b.num_tets());
  const std::vector<int> same = matching_tets(a, a);
  for (int t = 0; t < a.num_tets(); ++t) ASSERT_EQ(same[t], t);
  EXPECT_TRUE(matching_tets(a, build_fluid_mesh(mesh::structured_box(kLo, kHi, 6, 5, 3))).empty());
}

TEST(FluidOperators, GeometryUpdateOfAMovedMeshEqualsAFreshBuildBitForBit) {
  // A box with a solid block inside (so that boundary faces toward a solid exist too), then the
  // same tets with every interior vertex moved: updating the first fluid mesh's geometry must
  // give exactly what building the moved mesh from scratch gives, tet by tet, node by node and
  // face by face. The fresh build may number them otherwise (build_fluid_mesh orders the tets
  // along a curve through their centroids), so they are matched through the TetMesh ids; the
  // dual volumes, sums over each node's tets in numbering order, agree to round-off.
  std::mt19937 rng(7);
  mesh::TetMesh base = mesh::structured_box(kLo, kHi, 8, 6, 4);
  for (int t = 0; t < base.num_tets(); ++t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) c += 0.25 * base.vertices[base.tets[t][k]];
    if ((c - Eigen::Vector3d(0.5, 0.375, 0.25)).cwiseAbs().maxCoeff() < 0.15) base.subdomain[t] = mesh::solid_subdomain(0);
  }
  FluidMesh updated = build_fluid_mesh(testing::jittered(base, kLo, kHi, 0.125, 0.1, rng));
  const mesh::TetMesh moved = testing::jittered(base, kLo, kHi, 0.125, 0.1, rng);
  update_fluid_mesh_geometry(moved, updated);
  const FluidMesh fresh = build_fluid_mesh(moved);
  ASSERT_EQ(updated.num_tets(), fresh.num_tets());
  ASSERT_EQ(updated.num_nodes(), fresh.num_nodes());
  ASSERT_EQ(updated.boundary_faces.size(), fresh.boundary_faces.size());
  int solid_faces = 0;
  for (const BoundaryFace& f : fresh.boundary_faces) solid_faces += f.other_subdomain != 0;
  EXPECT_GT(solid_faces, 0);
  std::vector<int> fresh_tet(moved.num_tets(), -1);  // TetMesh tet -> fresh fluid tet
  for (int t = 0; t < fresh.num_tets(); ++t) fresh_tet[fresh.tet_to_mesh_tet[t]] = t;
  auto fresh_node = [&](int i) { return fresh.mesh_vertex_to_node[updated.node_to_mesh_vertex[i]]; };
  for (int i = 0; i < updated.num_nodes(); ++i) {
    ASSERT_EQ(updated.nodes[i], fresh.nodes[fresh_node(i)]) << i;
    ASSERT_NEAR(updated.dual_volume[i], fresh.dual_volume[fresh_node(i)], 1e-15 * fresh.dual_volume[fresh_node(i)]) << i;
  }
  for (int t = 0; t < updated.num_tets(); ++t) {
    const int u = fresh_tet[updated.tet_to_mesh_tet[t]];
    ASSERT_GE(u, 0) << t;
    ASSERT_EQ(updated.volume[t], fresh.volume[u]) << t;
    ASSERT_EQ(updated.centroid(t), fresh.centroid(u)) << t;
    for (int k = 0; k < 4; ++k) {
      ASSERT_EQ(fresh_node(updated.tets[t][k]), fresh.tets[u][k]) << t;
      ASSERT_EQ(updated.grad[t][k], fresh.grad[u][k]) << t;
      const int n = updated.neighbor[t][k];
      ASSERT_EQ(n < 0 ? -1 : fresh_tet[updated.tet_to_mesh_tet[n]], fresh.neighbor[u][k]) << t;
    }
  }
  for (std::size_t f = 0; f < fresh.boundary_faces.size(); ++f) {  // faces are ordered by TetMesh vertex ids
    const BoundaryFace &a = updated.boundary_faces[f], &b = fresh.boundary_faces[f];
    ASSERT_EQ(fresh_tet[updated.tet_to_mesh_tet[a.tet]], b.tet) << f;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(fresh_node(a.nodes[k]), b.nodes[k]) << f;
    ASSERT_EQ(a.normal, b.normal) << f;
    ASSERT_EQ(a.area, b.area) << f;
  }
  // An update that inverts a tet is refused like a build.
  mesh::TetMesh inverted = moved;
  inverted.vertices[base.tets[0][3]] = inverted.vertices[base.tets[0][0]];
  EXPECT_THROW(update_fluid_mesh_geometry(inverted, updated), std::invalid_argument);
}

}  // namespace
}  // namespace tetfsi::fluid
