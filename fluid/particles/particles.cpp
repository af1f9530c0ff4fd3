#include "fluid/particles/particles.hpp"

#include <utility>

namespace tetfsi::fluid {
namespace {

template <class T>
void keep_entries(std::vector<T>& values, const std::vector<char>& keep) {
  if (values.empty()) return;
  std::size_t n = 0;
  for (std::size_t p = 0; p < keep.size(); ++p)
    if (keep[p]) values[n++] = values[p];
  values.resize(n);
}

template <class T>
void permute(std::vector<T>& values, const std::vector<int>& order) {
  if (values.empty()) return;
  std::vector<T> out(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) out[k] = values[order[k]];
  values = std::move(out);
}

}  // namespace

void ParticleSet::keep_only(const std::vector<char>& keep) {
  keep_entries(x, keep);
  keep_entries(v, keep);
  keep_entries(grad_v, keep);
  keep_entries(tet, keep);
}

std::vector<int> ParticleSet::tet_ranges(int num_tets) const {
  std::vector<int> first(num_tets + 1, 0);
  for (int t : tet) ++first[t + 1];
  for (int t = 0; t < num_tets; ++t) first[t + 1] += first[t];
  return first;
}

void ParticleSet::sort_by_tet(int num_tets) {
  // Counting sort: stable, O(particles + tets), the same order on every thread count.
  std::vector<int> next = tet_ranges(num_tets);
  std::vector<int> order(tet.size());
  for (int p = 0; p < size(); ++p) order[next[tet[p]]++] = p;
  permute(x, order);
  permute(v, order);
  permute(grad_v, order);
  permute(tet, order);
}

}  // namespace tetfsi::fluid
