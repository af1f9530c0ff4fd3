// Cut-tet geometry of the free-surface projection (fluid/liquid/cut_tet.hpp): the liquid volume of
// a tet cut by a plane, and the wet moments a_k, which must reproduce a linear pressure that
// vanishes on the plane exactly (sum_k a_k p_k = |Omega| grad p) and reduce to V grad(phi_k) on a
// fully wet tet; and the first moment int x dV of the liquid part. The wet face mass
// M_ka = (1/A) int_{F wet} psi_k phi_a dA (the coupled interface map of a liquid) must sum over a
// and the tet's faces to a_k, reproduce int p phi_a over the wet part for a linear p vanishing on
// the surface (against sampling), and be the P1 mass (1 + delta) / 12 on a wet face. A mirrored tet
// has the mirrored moments (no dependence on the order of the nodes).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "fluid/liquid/cut_tet.hpp"

namespace tetfsi::fluid {
namespace {

struct RandomCase {
  std::array<Eigen::Vector3d, 4> x;
  Eigen::Vector3d normal;
  double offset;
  std::array<double, 4> phi;
};

/// A positively oriented random tet and a random plane phi = n.x - d through it.
RandomCase random_case(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  RandomCase c;
  for (;;) {
    for (auto& p : c.x) p = Eigen::Vector3d(u(rng), u(rng), u(rng));
    const double v = (c.x[1] - c.x[0]).cross(c.x[2] - c.x[0]).dot(c.x[3] - c.x[0]) / 6.0;
    if (std::abs(v) < 0.05) continue;
    if (v < 0) std::swap(c.x[2], c.x[3]);
    break;
  }
  c.normal = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
  const Eigen::Vector3d centroid = (c.x[0] + c.x[1] + c.x[2] + c.x[3]) / 4.0;
  c.offset = c.normal.dot(centroid) + 0.4 * u(rng);
  for (int k = 0; k < 4; ++k) c.phi[k] = c.normal.dot(c.x[k]) - c.offset;
  return c;
}

TEST(CutTet, LinearPressureVanishingOnTheSurfaceIsExact) {
  std::mt19937 rng(3);
  int cut = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const RandomCase c = random_case(rng);
    const CutTet ct = cut_tet(c.x, c.phi);
    // p = -alpha phi: zero on the plane, positive in the liquid.
    const double alpha = 2.5;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) {
      if (c.phi[k] >= 0) {
        EXPECT_EQ(ct.wet_moment[k].norm(), 0.0);
        continue;
      }
      sum += ct.wet_moment[k] * (-alpha * c.phi[k]);
    }
    const Eigen::Vector3d expected = ct.liquid_volume * (-alpha * c.normal);
    EXPECT_LE((sum - expected).norm(), 1e-12 * (1.0 + expected.norm())) << "trial " << trial;
    int liquid = 0;
    for (double p : c.phi) liquid += p < 0;
    cut += liquid > 0 && liquid < 4;
  }
  EXPECT_GT(cut, 1000);  // the planes really cut most tets (1, 2 and 3 liquid nodes)
}

TEST(CutTet, LiquidVolumeMatchesSampling) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 40; ++trial) {
    const RandomCase c = random_case(rng);
    const double f = liquid_fraction(c.phi);
    // Sample the tet uniformly on a barycentric lattice (n^3/6 points) and count the liquid ones.
    const int n = 120;
    long inside = 0, total = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j)
        for (int k = 0; i + j + k < n; ++k) {
          const double l1 = (i + 0.25) / n, l2 = (j + 0.25) / n, l3 = (k + 0.25) / n, l0 = 1 - l1 - l2 - l3;
          const double phi = l0 * c.phi[0] + l1 * c.phi[1] + l2 * c.phi[2] + l3 * c.phi[3];
          inside += phi < 0;
          ++total;
        }
    EXPECT_NEAR(f, static_cast<double>(inside) / total, 0.02) << "trial " << trial;
    // Complement: the air part of phi is the liquid part of -phi.
    EXPECT_NEAR(f + liquid_fraction({-c.phi[0], -c.phi[1], -c.phi[2], -c.phi[3]}), 1.0, 1e-13);
  }
}

TEST(CutTet, FirstMomentMatchesSamplingAndItsComplement) {
  // int_{Omega} x dV (the liquid's gravity potential): the liquid part's and the air part's (the
  // liquid part of -phi) add up to V times the centroid to round-off, and the liquid part's centroid
  // agrees with the mean of lattice points in the liquid.
  std::mt19937 rng(9);
  for (int trial = 0; trial < 40; ++trial) {
    const RandomCase c = random_case(rng);
    const double volume = (c.x[1] - c.x[0]).cross(c.x[2] - c.x[0]).dot(c.x[3] - c.x[0]) / 6.0;
    const Eigen::Vector3d centroid = (c.x[0] + c.x[1] + c.x[2] + c.x[3]) / 4.0;
    const Eigen::Vector3d m = liquid_first_moment(c.x, c.phi);
    const Eigen::Vector3d m_air = liquid_first_moment(c.x, {-c.phi[0], -c.phi[1], -c.phi[2], -c.phi[3]});
    EXPECT_LE((m + m_air - volume * centroid).norm(), 1e-13 * (1 + volume * centroid.norm())) << "trial " << trial;
    EXPECT_NEAR(cut_tet(c.x, c.phi).first_moment.x(), m.x(), 1e-15);
    const double f = liquid_fraction(c.phi);
    if (f < 0.05) continue;  // too few lattice points for a mean
    const int n = 120;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    long inside = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j)
        for (int k = 0; i + j + k < n; ++k) {
          const double l1 = (i + 0.25) / n, l2 = (j + 0.25) / n, l3 = (k + 0.25) / n, l0 = 1 - l1 - l2 - l3;
          const double phi = l0 * c.phi[0] + l1 * c.phi[1] + l2 * c.phi[2] + l3 * c.phi[3];
          if (phi >= 0) continue;
          sum += l0 * c.x[0] + l1 * c.x[1] + l2 * c.x[2] + l3 * c.x[3];
          ++inside;
        }
    const double size = (c.x[1] - c.x[0]).norm();
    EXPECT_LE((m / (f * volume) - sum / inside).norm(), 0.02 * size) << "trial " << trial;
  }
  const RandomCase c = random_case(rng);
  const double volume = (c.x[1] - c.x[0]).cross(c.x[2] - c.x[0]).dot(c.x[3] - c.x[0]) / 6.0;
  const Eigen::Vector3d wet = liquid_first_moment(c.x, {-1, -1, -1, -1});
  EXPECT_LE((wet - volume * (c.x[0] + c.x[1] + c.x[2] + c.x[3]) / 4.0).norm(), 1e-14);
}

TEST(CutTet, AMirroredTetHasTheMirroredWetMoments) {
  // The wet moments depend on the tet's geometry and values alone, not on the order of its nodes:
  // the mirror image z -> -z (two nodes exchanged to keep the orientation) of a cut tet has the
  // mirror images of its a_k. Splitting each wet quad along the diagonal from its first node, as
  // a global node numbering did, failed this by up to a third of a face's share.
  std::mt19937 rng(7);
  const Eigen::Vector3d flip(1, 1, -1);
  for (int trial = 0; trial < 2000; ++trial) {
    const RandomCase c = random_case(rng);
    std::array<Eigen::Vector3d, 4> x = c.x;
    std::array<double, 4> phi = c.phi;
    for (auto& p : x) p = p.cwiseProduct(flip);
    std::swap(x[0], x[1]);
    std::swap(phi[0], phi[1]);
    const CutTet a = cut_tet(c.x, c.phi), b = cut_tet(x, phi);
    const int image[4] = {1, 0, 2, 3};
    for (int k = 0; k < 4; ++k)
      EXPECT_LE((b.wet_moment[image[k]] - a.wet_moment[k].cwiseProduct(flip)).norm(), 1e-14) << "trial " << trial;
    EXPECT_NEAR(b.liquid_volume, a.liquid_volume, 1e-15);
  }
}

TEST(CutTet, FullyWetTetGivesTheP1HatGradients) {
  const std::array<Eigen::Vector3d, 4> x = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0.1, 0),
                                            Eigen::Vector3d(0.2, 1, 0), Eigen::Vector3d(0.1, 0.3, 0.9)};
  const CutTet c = cut_tet(x, {-1, -2, -1.5, -0.5});
  Eigen::Matrix4d m;
  for (int k = 0; k < 4; ++k) m.row(k) << 1, x[k].transpose();
  const Eigen::Matrix4d inv = m.inverse();  // column k: coefficients of hat k
  const double v = m.determinant() / 6.0;
  EXPECT_NEAR(c.liquid_volume, v, 1e-15);
  for (int k = 0; k < 4; ++k)
    EXPECT_LE((c.wet_moment[k] - v * inv.block<3, 1>(1, k)).norm(), 1e-14) << "node " << k;
}

/// The faces of a tet as local vertex triples, counter-clockwise seen from outside (cut_tet.cpp).
constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

TEST(CutTet, WetFaceMassSumsToTheWetMoments) {
  // sum_F s_F sum_a M_ka(F) = a_k: a solid face moving with the liquid carries the flux the
  // liquid's weak divergence has for the same velocity.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 2000; ++trial) {
    const RandomCase c = random_case(rng);
    const CutTet ct = cut_tet(c.x, c.phi);
    std::array<Eigen::Vector3d, 4> sum{};
    for (auto& s : sum) s.setZero();
    for (const auto& f : kFaces) {
      const Eigen::Vector3d s = 0.5 * (c.x[f[1]] - c.x[f[0]]).cross(c.x[f[2]] - c.x[f[0]]);
      const auto m = wet_face_mass({c.phi[f[0]], c.phi[f[1]], c.phi[f[2]]});
      for (int k = 0; k < 3; ++k) sum[f[k]] += (m[k][0] + m[k][1] + m[k][2]) * s;
    }
    for (int k = 0; k < 4; ++k)
      EXPECT_LE((sum[k] - ct.wet_moment[k]).norm(), 1e-13) << "trial " << trial << " node " << k;
  }
}

TEST(CutTet, WetFaceMassIntegratesALinearPressureOverTheWetPart) {
  // p = -phi (zero on the surface, linear): sum_k p_k M_ka = (1/A) int_{phi<0} p phi_a dA, against
  // the centroid rule on the face split into 400^2 equal triangles (p phi_a vanishes on the
  // surface, so the cells it cuts err by O(cell^3) each: about 1e-5 in all).
  const int n = 400;
  const std::array<std::array<double, 3>, 4> cases = {{{-1, 0.5, 0.8}, {-1, -0.3, 0.6}, {-0.2, -0.7, 0.9},
                                                       {0.4, -0.5, 0.1}}};
  for (const auto& phi : cases) {
    Eigen::Vector3d quadrature = Eigen::Vector3d::Zero();
    const auto add = [&](double a, double b) {  // a sub-triangle's centroid, in face coordinates
      const Eigen::Vector3d bary(1 - a - b, a, b);
      const double phi_x = bary[0] * phi[0] + bary[1] * phi[1] + bary[2] * phi[2];
      if (phi_x < 0) quadrature += (-phi_x) * bary / (double(n) * n);
    };
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        add((i + 1.0 / 3) / n, (j + 1.0 / 3) / n);
        if (i + j < n - 1) add((i + 2.0 / 3) / n, (j + 2.0 / 3) / n);
      }
    const auto m = wet_face_mass(phi);
    for (int a = 0; a < 3; ++a) {
      double exact = 0;
      for (int k = 0; k < 3; ++k) exact += (phi[k] < 0 ? -phi[k] : 0.0) * m[k][a];
      EXPECT_NEAR(exact, quadrature[a], 1e-4) << "phi " << phi[0] << " " << phi[1] << " " << phi[2] << ", a " << a;
    }
  }
}

TEST(CutTet, WetFaceMassIsTheP1MassOnAWetFaceAndZeroOnADryOne) {
  const auto wet = wet_face_mass({-1, -0.2, -3});
  const auto dry = wet_face_mass({1, 0.2, 0});
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) {
      EXPECT_DOUBLE_EQ(wet[k][a], (k == a ? 2.0 : 1.0) / 12.0);
      EXPECT_EQ(dry[k][a], 0.0);
    }
}

}  // namespace
}  // namespace tetfsi::fluid
