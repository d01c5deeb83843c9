#pragma once
// Sorting 64-bit keys by their bytes: millions of keys (a cloud's points by voxel, by
// coordinates) sort several times faster than by comparisons.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

  // Sorts `keys` ascending: least significant byte first, a byte that every key shares skipped;
  // the counts of all eight bytes come from one pass. Short lists go to std::sort.
  inline void radix_sort(std::vector<std::uint64_t> & keys) {
    constexpr std::size_t kRadixFrom = 128;  // shorter lists: a comparison sort is as fast
    const std::size_t n = keys.size();
    if (n < kRadixFrom) {
      std::sort(keys.begin(), keys.end());
      return;
    }
    std::size_t starts[8][257] = {};
    for (const std::uint64_t key : keys)
      for (int byte = 0; byte < 8; ++byte) ++starts[byte][((key >> (8 * byte)) & 0xff) + 1];
    std::vector<std::uint64_t> sorted(n);
    for (int byte = 0; byte < 8; ++byte) {
      std::size_t* start = starts[byte];
      if (std::find(start + 1, start + 257, n) != start + 257) continue;
      std::partial_sum(start, start + 257, start);
      for (const std::uint64_t key : keys) sorted[start[(key >> (8 * byte)) & 0xff]++] = key;
      keys.swap(sorted);
    }
  }

}  // namespace )
}  // namespace vmas
