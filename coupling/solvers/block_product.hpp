#pragma once
/// @file block_product.hpp
/// Private: the products of eq. (7)'s blocks that the lagged GMRES takes every iteration, in
/// parallel and independent of the thread count.
///
/// A column-major matrix M gives Mᵀx as one dot product per column, so each output entry is one
/// sequential sum in storage order whichever thread computes it (Mx would scatter into shared
/// entries). A = M/h + C + (h/2)K′ (eq. 4) and P = (h/ρ)L are symmetric, so A x = Aᵀ x and
/// P x = Pᵀ x; H x needs Hᵀ stored, which BlockProducts keeps (H is small: interface nodes only).
#include <Eigen/Core>

#include "coupling/coupled_system.hpp"

namespace tetfsi::coupling::detail {

class BlockProducts {
 public:
  /// Keeps references to s's blocks (s must outlive this) and a transposed copy of s.H.
  explicit BlockProducts(const CoupledSystem& s);

  /// yᵤ = (A xᵤ − Hᵀ xₚ) / solid_scale and yₚ = (H xᵤ + P xₚ) / fluid_scale: the rows of eq. (7)
  /// as written in the paper, [A −Hᵀ; H P], each divided by its scale.
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y, double solid_scale, double fluid_scale) const;
  /// y = H x (x of size n, y of size m).
  void interface_flux(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::VectorXd& y) const;

 private:
  const CoupledSystem& s_;
  SparseMatrix H_transpose_;  // n x m
};

}  // namespace tetfsi::coupling::detail
