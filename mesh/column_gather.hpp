#pragma once
/// @file column_gather.hpp
/// Assembly of a finite-element matrix K = Σ_e Σ_{a,b} k_e(a, b) e_{row(a)} e_{col(b)}ᵀ column by
/// column, in parallel, straight into Eigen's compressed column storage: column c gathers the terms
/// of the elements around its vertex, so that nothing is scattered (no triplet list, about 16
/// entries per tet, and no serial sort of it) and each entry is the sum of its terms in the order
/// the caller emits them (in element order, that is a triplet sum in element order, bit for bit).
/// Written here because Eigen assembles from triplets only; the gather is the same for the fluid's
/// P1 Laplacian (fluid/operators) and the mesh motion's stiffened Laplacian (mesh_motion.cpp).
#include <Eigen/SparseCore>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <utility>
#include <vector>

namespace tetfsi::mesh {

/// @param num_rows, num_columns  the matrix's size
/// @param for_each_term  for_each_term(c, emit) calls emit(r, value) for every term of column c
///                       (row r in [0, num_rows), `value` a callable giving the term's value; it is
///                       called only when values are gathered, so the counting pass skips it)
/// @param scale          multiplies every entry
/// @param earlier        optional: a matrix gathered before (the same mesh moved, say). If the terms
///                       fall on exactly its entries, column by column, its pattern is reused: the
///                       values are summed straight into it in one pass, with no counting pass and no
///                       sort, and the result is bit for bit what the full gather gives (the same
///                       terms in the same order), and takes over `earlier`'s storage (which is
///                       left empty). Otherwise the full gather runs. Its values are overwritten
///                       either way.
template <class ForEachTerm>
Eigen::SparseMatrix<double> gather_columns(int num_rows, int num_columns, const ForEachTerm& for_each_term,
                                           double scale = 1.0, Eigen::SparseMatrix<double>* earlier = nullptr) {
  Eigen::SparseMatrix<double> k(num_rows, num_columns);
  if (num_rows == 0 || num_columns == 0) return k;
  // Per thread: slot[r] = position of row r in the column being gathered, -1 if absent (reset
  // after each column), so each term finds its entry in O(1).
  tbb::enumerable_thread_specific<std::vector<int>> slots([num_rows] { return std::vector<int>(num_rows, -1); });
  if (earlier && earlier->rows() == num_rows && earlier->cols() == num_columns && earlier->isCompressed()) {
    Eigen::SparseMatrix<double>& m = *earlier;
    const auto* start = m.outerIndexPtr();
    const auto* row = m.innerIndexPtr();
    double* value = m.valuePtr();
    std::atomic<bool> same{true};
    tbb::parallel_for(tbb::blocked_range<int>(0, num_columns), [&](const tbb::blocked_range<int>& range) {
      std::vector<int>& slot = slots.local();
      std::vector<char> touched;
      for (int c = range.begin(); c < range.end() && same.load(std::memory_order_relaxed); ++c) {
        const int first = start[c], size = start[c + 1] - start[c];
        touched.assign(size, 0);
        for (int e = 0; e < size; ++e) {
          slot[row[first + e]] = e;
          value[first + e] = 0.0;
        }
        bool fits = true;
        for_each_term(c, [&](int r, const auto& term) {
          if (slot[r] < 0) {
            fits = false;
            return;
          }
          touched[slot[r]] = 1;
          value[first + slot[r]] += term();
        });
        for (int e = 0; e < size; ++e) {
          slot[row[first + e]] = -1;
          fits = fits && touched[e];
          value[first + e] *= scale;
        }
        if (!fits) same = false;
      }
    });
    if (same) {
      k.swap(m);  // Eigen 3.4's SparseMatrix has no move constructor: swap, not copy
      return k;
    }
  }
  // One column's entries, rows ascending; with `values` false only the rows (for the counts).
  auto column = [&](int c, std::vector<int>& slot, std::vector<std::pair<int, double>>& entries, bool values) {
    entries.clear();
    for_each_term(c, [&](int r, const auto& value) {
      if (slot[r] < 0) {
        slot[r] = static_cast<int>(entries.size());
        entries.emplace_back(r, 0.0);
      }
      if (values) entries[slot[r]].second += value();
    });
    for (const auto& e : entries) slot[e.first] = -1;
    std::sort(entries.begin(), entries.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  };
  std::vector<int> start(num_columns + 1, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, num_columns), [&](const tbb::blocked_range<int>& range) {
    std::vector<int>& slot = slots.local();
    std::vector<std::pair<int, double>> entries;
    for (int c = range.begin(); c < range.end(); ++c) {
      column(c, slot, entries, false);
      start[c + 1] = static_cast<int>(entries.size());
    }
  });
  for (int c = 0; c < num_columns; ++c) start[c + 1] += start[c];
  k.resizeNonZeros(start[num_columns]);
  std::copy(start.begin(), start.end(), k.outerIndexPtr());
  tbb::parallel_for(tbb::blocked_range<int>(0, num_columns), [&](const tbb::blocked_range<int>& range) {
    std::vector<int>& slot = slots.local();
    std::vector<std::pair<int, double>> entries;
    for (int c = range.begin(); c < range.end(); ++c) {
      column(c, slot, entries, true);
      for (std::size_t e = 0; e < entries.size(); ++e) {
        k.innerIndexPtr()[start[c] + e] = entries[e].first;
        k.valuePtr()[start[c] + e] = scale * entries[e].second;
      }
    }
  });
  return k;
}

}  // namespace tetfsi::mesh
