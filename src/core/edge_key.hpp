#pragma once
// One key per undirected edge of a mesh: its two vertex indices, the smaller first.
#include <cstdint>
#include <utility>

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

inline std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

}  // namespace internal
}  // namespace vmas
