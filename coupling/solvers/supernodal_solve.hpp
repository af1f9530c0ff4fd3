#pragma once
/// @file supernodal_solve.hpp
/// The two triangular solves with a supernodal Cholesky factor L Lᵀ = Q A Qᵀ (CHOLMOD's storage):
///
///     x = A⁻¹ b = Qᵀ L⁻ᵀ L⁻¹ Q b,
///
/// L⁻¹ by supernodes in order (forward) and L⁻ᵀ in reverse order (backward). Supernode k holds the
/// columns [c₀, c₁) of L as one dense column-major block of `rows` × (c₁ − c₀): its top square is
/// the lower triangle L_kk, its rows below are L_rk on the row indices `row_index`, so
///
///     forward:   y_k ← L_kk⁻¹ y_k,           y_r ← y_r − L_rk y_k,
///     backward:  y_k ← y_k − L_rkᵀ y_r,      y_k ← L_kk⁻ᵀ y_k.
///
/// Written here because CHOLMOD 3 (Debian 12's SuiteSparse 5.12) makes each supernode's solve a
/// BLAS call that takes OpenBLAS's global buffer lock and allocates its workspace on every solve:
/// with the flagship's two sheets solved side by side the locks serialize them (measured at 962k
/// fluid tets, two factors of 7.8M entries: CHOLMOD 16.1 ms one after the other, 17.1 ms side by
/// side; this solve 12.2 and 6.3 ms, the same solution to 6e-16 relative).
#include <vector>

namespace tetfsi::coupling::detail {

/// A supernodal factor's arrays, as CHOLMOD stores them (cholmod_factor with is_super, int indices),
/// with its values in double or in single precision (Scalar).
/// Inputs:
///   n             unknowns
///   num_supernodes
///   first_column  [num_supernodes + 1]: supernode k holds columns first_column[k] .. first_column[k+1]−1
///   first_row     [num_supernodes + 1]: its row indices are row_index[first_row[k] .. first_row[k+1]−1]
///                 (the first c₁ − c₀ of them are its own columns)
///   first_value   [num_supernodes + 1]: its block starts at values[first_value[k]], column-major
///   row_index     row indices of every supernode
///   permutation   [n]: Q, row i of Q A Qᵀ is row permutation[i] of A
///   values        the dense blocks of L
template <class Scalar>
struct SupernodalFactorView {
  int n = 0, num_supernodes = 0;
  const int *first_column = nullptr, *first_row = nullptr, *first_value = nullptr;
  const int *row_index = nullptr, *permutation = nullptr;
  const Scalar* values = nullptr;
};

/// Work vectors of one solve (sized on first use, kept between solves).
template <class Scalar>
struct SupernodalWorkspace {
  std::vector<Scalar> y, gathered;
};

/// x = A⁻¹ b with the factor `L` of A (see the file comment), in L's precision. b and x: n entries
/// each (b is read whole before x is written, so they may be the same array).
template <class Scalar>
void supernodal_solve(const SupernodalFactorView<Scalar>& L, const double* b, double* x,
                      SupernodalWorkspace<Scalar>& work);

extern template void supernodal_solve<double>(const SupernodalFactorView<double>&, const double*, double*,
                                              SupernodalWorkspace<double>&);
extern template void supernodal_solve<float>(const SupernodalFactorView<float>&, const double*, double*,
                                             SupernodalWorkspace<float>&);

}  // namespace tetfsi::coupling::detail
