#pragma once
// Union-find with path halving; the smaller index is the root of a union, so roots (and the
// order of sets) do not depend on the order of the unions.
#include <algorithm>
#include <numeric>
#include <vector>

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

class DisjointSets {
 public:
  explicit DisjointSets(int count) : parent_(count), sets_(count) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int find(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  // False when a and b were in one set already.
  bool unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent_[std::max(a, b)] = std::min(a, b);
    --sets_;
    return true;
  }
  int sets() const { return sets_; }

 private:
  std::vector<int> parent_;
  int sets_;
};

}  // namespace internal
}  // namespace vmas
