#pragma once
/// @file quad_frame.hpp
/// Co-rotational kinematics of the 4-node Belytschko-Tsay membrane quad at its centre
/// (Lian, Liu & Zhang 2014, section 4; Hallquist 1998; Belytschko, Lin & Tsay 1984).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>

namespace tetfsi::mpm {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/// Frame and one-point B-matrix of a quad with nodes x1..x4 (counter-clockwise about e3).
struct QuadFrame {
  /// [q] of eq. (39): columns e1, e2, e3 (global components of the local unit vectors).
  Mat3 q = Mat3::Identity();
  Vec3 center = Vec3::Zero();        ///< mean of the nodes
  std::array<double, 4> xl{}, yl{};  ///< local in-plane node coordinates q^T (x_K - center)
  std::array<double, 4> zl{};        ///< local out-of-plane offsets (warpage)
  double area = 0;                   ///< A = 1/2 (x31 y42 + x24 y31) in the local plane [m^2]
  /// B_1K = dN_K/dx, B_2K = dN_K/dy at the centre (xi = eta = 0):
  /// B_1 = [y24, y31, y42, y13] / (2A), B_2 = [x42, x13, x24, x31] / (2A).
  std::array<double, 4> b1{}, b2{};
  /// Flanagan-Belytschko hourglass shape vector gamma_K = 1/4 [h_K - (h.x) B_1K - (h.y) B_2K],
  /// h = (1, -1, 1, -1); orthogonal to every linear field, so rigid and uniform motions give no
  /// hourglass rate.
  std::array<double, 4> gamma{};
  /// Vector area S = 1/2 (x3 - x1) x (x4 - x2) (exact for a bilinear quad), along e3.
  Vec3 area_vector = Vec3::Zero();
};

/// Builds the frame of eqs. (32)-(39):
///   chi = r21 + r34, psi = r31 + r42 (r_IJ = x_I - x_J), e3 = chi x psi / |chi x psi|,
///   alpha = (chi + psi)/|chi + psi|, beta = e3 x alpha / |e3 x alpha|,
///   e1 = (alpha - beta)/sqrt 2, e2 = (alpha + beta)/sqrt 2,
/// and the centre B-matrix and hourglass vector in that frame.
/// @throws std::runtime_error if the quad is degenerate (zero or negative local area)
QuadFrame quad_frame(const std::array<Vec3, 4>& x);

}  // namespace tetfsi::mpm
