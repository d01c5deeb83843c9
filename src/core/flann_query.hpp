#pragma once
// FLANN's knnSearch and radiusSearch for a single query, without the OpenMP region both open on
// every call (its closing system call costs more than one search). Same result sets and
// ordering as FLANN's, so the same neighbours, for an index no point was removed from.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <flann/flann.hpp>
#include <limits>
#include <numeric>
#include <type_traits>
#include <vector>

#include "core/radix_sort.hpp"

// Hidden: internal to the library, never exported (src/exports.map exports the vmas API).
namespace vmas {
namespace flann_query __attribute__((visibility("hidden"))) {

// The `k` nearest points (k at most the index's size): their ids in found[0, n) and squared
// distances in squared[0, n), nearest first; returns n.
template <class Index, class T>
std::size_t k_nearest(const Index& index, const T* query, std::size_t k, std::size_t* found,
                      T* squared, const flann::SearchParams& params) {
  std::size_t n = 0;
  const auto search = [&](auto& result) {
    result.clear();
    index.findNeighbors(result, query, params);
    n = std::min(result.size(), k);
    if (n > 0) result.copy(found, squared, n, params.sorted);
  };
  const bool heap = params.use_heap == flann::FLANN_Undefined
                        ? k > KNN_HEAP_THRESHOLD
                        : params.use_heap == flann::FLANN_True;
  if (heap) {
    flann::KNNResultSet2<T> result(k);
    search(result);
  } else {
    flann::KNNSimpleResultSet<T> result(k);
    search(result);
  }
  return n;
}

// found/squared sorted as FLANN sorts results (nearest first, lower index among equals), by one
// integer key per result (the bits of a non-negative float order as the float does) and a radix
// sort (radix_sort.hpp): sorting FLANN's (distance, index) pairs was a tenth of a noisy cloud's
// run.
inline void sort_nearest_first(std::vector<std::size_t>& found, std::vector<float>& squared) {
  const std::size_t n = found.size();
  std::vector<std::uint64_t> keys(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, &squared[i], sizeof bits);
    keys[i] = (std::uint64_t{bits} << 32) | found[i];
  }
  internal::radix_sort(keys);
  for (std::size_t i = 0; i < n; ++i) {
    const auto bits = static_cast<std::uint32_t>(keys[i] >> 32);
    std::memcpy(&squared[i], &bits, sizeof bits);
    found[i] = keys[i] & 0xffffffffu;
  }
}

// The points within `squared_radius`, at most `max_neighbors` of them (0: all) in `found` and
// `squared`; returns how many are within the radius (before the cap), as FLANN does.
template <class Index, class T>
std::size_t within_radius(const Index& index, const T* query, T squared_radius,
                          std::size_t max_neighbors, std::vector<std::size_t>& found,
                          std::vector<T>& squared, const flann::SearchParams& params) {
  std::size_t count = 0;
  const auto search = [&](auto& result, std::size_t cap, bool sorted) {
    result.clear();
    index.findNeighbors(result, query, params);
    count = result.size();
    const std::size_t kept = std::min(count, cap);
    found.resize(kept);
    squared.resize(kept);
    if (kept > 0) result.copy(found.data(), squared.data(), kept, sorted);
  };
  if (max_neighbors == 0) {
    // Indices fit the key's 32 bits: FLANN's are those of a cloud held in memory.
    constexpr bool kByKey = std::is_same_v<T, float>;
    flann::RadiusResultSet<T> result(squared_radius);
    search(result, std::numeric_limits<std::size_t>::max(), params.sorted && !kByKey);
    if constexpr (kByKey)
      if (params.sorted) sort_nearest_first(found, squared);
  } else {
    flann::KNNRadiusResultSet<T> result(squared_radius, max_neighbors);
    search(result, max_neighbors, params.sorted);
  }
  return count;
}

}  // namespace flann_query
}  // namespace vmas
