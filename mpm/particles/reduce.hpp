#pragma once
/// @file reduce.hpp
/// Deterministic reduction over [0, n) with a fixed grain, run serially for small n; a loop over
/// [0, n) run serially or in parallel.
///
/// tbb::parallel_deterministic_reduce with a simple_partitioner splits [b, e) at b + (e - b) / 2
/// while e - b > grain, runs every leaf from the identity and joins each pair as join(left, right):
/// the result does not depend on the thread count. Below `serial_below` items the same tree is
/// evaluated recursively on the calling thread (bit-identical to the parallel result, without the
/// task overhead that dominates small problems stepped many times, e.g. the gas expansion of
/// Lian, Liu & Zhang 2014, section 7.3: 2,736 particles, 65,890 steps).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <cstddef>

namespace tetfsi::mpm {

namespace detail {
template <class Value, class Body, class Join>
Value reduce_tree(std::size_t b, std::size_t e, std::size_t grain, const Value& identity, const Body& body,
                  const Join& join) {
  if (e - b <= grain) return body(tbb::blocked_range<std::size_t>(b, e, grain), identity);
  const std::size_t mid = b + (e - b) / 2u;
  const Value left = reduce_tree(b, mid, grain, identity, body, join);
  return join(left, reduce_tree(mid, e, grain, identity, body, join));
}
}  // namespace detail

/// body(range, init) -> Value accumulates range into init; join(a, b) -> Value.
template <class Value, class Body, class Join>
Value deterministic_reduce(std::size_t n, std::size_t grain, std::size_t serial_below, const Value& identity,
                           const Body& body, const Join& join) {
  if (n == 0) return identity;
  if (n < serial_below) return detail::reduce_tree(0, n, grain, identity, body, join);
  return tbb::parallel_deterministic_reduce(tbb::blocked_range<std::size_t>(0, n, grain), identity, body, join,
                                            tbb::simple_partitioner());
}

/// Calls f(k) for k in [0, n): on the calling thread if `parallel` is false, else with
/// tbb::parallel_for (grain 4). f(k) must write only data of its own k (then the result does not
/// depend on the number of threads).
template <class F>
void for_each_index(std::size_t n, bool parallel, const F& f) {
  if (!parallel) {
    for (std::size_t k = 0; k < n; ++k) f(k);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t k = r.begin(); k != r.end(); ++k) f(k);
  });
}

}  // namespace tetfsi::mpm
