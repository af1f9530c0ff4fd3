#pragma once
/// @file tl_point.hpp
/// One Gauss point's share of the Total Lagrangian internal force and tangent (Bathe 1996,
/// Finite Element Procedures, sec. 6.3.2) for an element of N "nodes" whose gradient rows are
/// dN (N x 3, dN_a/dX_j). The hex8 uses it with its 8 nodes; the enhanced hex8
/// (hex8_enhanced.hpp) with 8 nodes + 3 incompatible modes, whose 3-vector amplitudes enter F
/// exactly as nodal displacements do.
///  - B_L column (a, k): rows [xx yy zz xy yz zx] = [F_k0 N_a,X, F_k1 N_a,Y, F_k2 N_a,Z,
///    F_k0 N_a,Y + F_k1 N_a,X, F_k1 N_a,Z + F_k2 N_a,Y, F_k2 N_a,X + F_k0 N_a,Z];
///  - f += w B_L^T S_voigt;  K += w (B_L^T D B_L + B_NL^T blockdiag(S,S,S) B_NL), the second term
///    being delta_kl dN_a . S dN_b for entry (a k, b l).
#include <Eigen/Core>

#include "solid/hex/material.hpp"

namespace tetfsi::solid::hex {

template <int N>
void add_tl_point(const Eigen::Matrix<double, N, 3>& dN, const Eigen::Matrix3d& F, const Eigen::Matrix3d& S,
                  const Matrix6d* D, double w, Eigen::Matrix<double, 3 * N, 1>* f,
                  Eigen::Matrix<double, 3 * N, 3 * N>* K) {
  Eigen::Matrix<double, 6, 3 * N> BL;
  for (int a = 0; a < N; ++a) {
    for (int k = 0; k < 3; ++k) {
      const int c = 3 * a + k;
      BL(0, c) = F(k, 0) * dN(a, 0);
      BL(1, c) = F(k, 1) * dN(a, 1);
      BL(2, c) = F(k, 2) * dN(a, 2);
      BL(3, c) = F(k, 0) * dN(a, 1) + F(k, 1) * dN(a, 0);
      BL(4, c) = F(k, 1) * dN(a, 2) + F(k, 2) * dN(a, 1);
      BL(5, c) = F(k, 2) * dN(a, 0) + F(k, 0) * dN(a, 2);
    }
  }
  if (f) {
    Vector6d Sv;
    for (int v = 0; v < 6; ++v) Sv(v) = S(kVoigt[v][0], kVoigt[v][1]);
    f->noalias() += w * (BL.transpose() * Sv);
  }
  if (K && D) {
    K->noalias() += w * (BL.transpose() * ((*D) * BL));  // K_L
    const Eigen::Matrix<double, N, N> G = w * (dN * S * dN.transpose());  // K_NL
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b)
        for (int k = 0; k < 3; ++k) (*K)(3 * a + k, 3 * b + k) += G(a, b);
  }
}

}  // namespace tetfsi::solid::hex
