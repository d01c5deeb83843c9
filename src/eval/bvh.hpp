#pragma once
// A bounding-volume hierarchy over boxes, for the evaluator's nearest-primitive and
// containing-primitive queries.
#include <algorithm>
#include <vector>

#include "eval/primitives.hpp"
#include "vmas/types.hpp"

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

// Bounding-volume hierarchy over boxes (median split on the longest axis). The queries take the
// exact per-item test as a callback, so one tree type serves primitives and input triangles.
class Bvh {
 public:
  explicit Bvh(const std::vector<Box>& boxes) : boxes_(boxes), items_(boxes.size()) {
    for (std::size_t i = 0; i < items_.size(); ++i) items_[i] = static_cast<int>(i);
    if (!items_.empty()) build(0, static_cast<int>(items_.size()));
  }

  // Smallest distance(item) over all items; distance(item) must be at least the distance from p
  // to the item's box, which is what prunes the search. Returns early, with some distance below
  // `stop_below`, once one is found (for callers that only need the values above it).
  // `hint`: an item likely to be near, tried first (a tight bound prunes sooner); set to the
  // nearest item found.
  template <class Distance>
  double nearest(const Vec3& p, Distance&& distance, double stop_below = -kInfinity,
                 int* hint = nullptr) const {
    double best = kInfinity;
    if (nodes_.empty()) return best;
    if (hint && *hint >= 0) best = distance(*hint);
    if (best < stop_below) return best;
    int stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (node.box.squaredExteriorDistance(p) >= best * best) continue;
      if (node.count > 0) {
        for (int i = node.first; i < node.first + node.count; ++i) {
          const double d = distance(items_[i]);
          if (d >= best) continue;
          best = d;
          if (hint) *hint = items_[i];
        }
        if (best < stop_below) return best;
        continue;
      }
      const int left = node.first, right = node.first + 1;
      const bool left_first = nodes_[left].box.squaredExteriorDistance(p) <
                              nodes_[right].box.squaredExteriorDistance(p);
      stack[top++] = left_first ? right : left;
      stack[top++] = left_first ? left : right;
    }
    return best;
  }

  // Whether accept(item) holds for some item whose box contains p.
  template <class Accept>
  bool any_containing(const Vec3& p, Accept&& accept) const {
    if (nodes_.empty()) return false;
    int stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!node.box.contains(p)) continue;
      if (node.count > 0) {
        for (int i = node.first; i < node.first + node.count; ++i) {
          if (accept(items_[i])) return true;
        }
        continue;
      }
      stack[top++] = node.first;
      stack[top++] = node.first + 1;
    }
    return false;
  }

 private:
  // Inner nodes: children at first and first + 1. Leaves: items_[first, first + count).
  struct Node {
    Box box;
    int first = 0;
    int count = 0;
  };
  static constexpr int kLeafSize = 4;
  static constexpr int kMaxDepth = 128;  // median splits: depth <= log2(n) + 1, two slots per level

  void build(int begin, int end) {
    nodes_.push_back({});
    build_node(static_cast<int>(nodes_.size()) - 1, begin, end);
  }

  void build_node(int index, int begin, int end) {
    Box box, centers;
    for (int i = begin; i < end; ++i) {
      box.extend(boxes_[items_[i]]);
      centers.extend(boxes_[items_[i]].center());
    }
    nodes_[index].box = box;
    if (end - begin <= kLeafSize) {
      nodes_[index].first = begin;
      nodes_[index].count = end - begin;
      return;
    }
    int axis = 0;
    centers.sizes().maxCoeff(&axis);
    const int middle = (begin + end) / 2;
    std::nth_element(
        items_.begin() + begin, items_.begin() + middle, items_.begin() + end,
        [&](int i, int j) { return boxes_[i].center()[axis] < boxes_[j].center()[axis]; });
    const int children = static_cast<int>(nodes_.size());
    nodes_[index].first = children;
    nodes_.resize(nodes_.size() + 2);
    build_node(children, begin, middle);
    build_node(children + 1, middle, end);
  }

  const std::vector<Box>& boxes_;
  std::vector<int> items_;
  std::vector<Node> nodes_;
};

}  // namespace internal
}  // namespace vmas
