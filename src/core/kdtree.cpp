#include "core/kdtree.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <flann/flann.hpp>
#include <limits>
#include <memory>
#include <mutex>
#include <utility>

#include "core/flann_query.hpp"
#include "vmas/error.hpp"

namespace vmas {

namespace {

constexpr int kLeafSize = 10;

struct Interval {
  double low, high;
};
using Box = std::array<Interval, 3>;

// The single nearest neighbour runs in the inner loop of the shrinking ball, so it has its own
// tree: the one FLANN's KDTreeSingleIndex builds (same splits, same leaves), and the same answers.
// FLANN's search descends into the nearer child first and returns, of the points at the least
// distance, those in the first leaf it reaches in that order, then the lowest index. This search
// keeps the order but prunes a node by its bounding box rather than FLANN's incremental bound:
// it skips more, but never a node holding a point at the least distance (the box distance is
// rounded no higher than any of its points' distances), so the same leaf wins.
// FLANN itself still serves the k-nearest queries.
class NearestTree {
 public:
  explicit NearestTree(const std::vector<Vec3>& points) {
    order_.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) order_[i] = static_cast<int>(i);
    Box box;
    for (int c = 0; c < 3; ++c) box[c] = {points[0][c], points[0][c]};
    for (const Vec3& p : points)
      for (int c = 0; c < 3; ++c) {
        if (p[c] < box[c].low) box[c].low = p[c];
        if (p[c] > box[c].high) box[c].high = p[c];
      }
    divide(points, 0, static_cast<int>(points.size()), box);
    coordinates_.resize(3 * points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
      for (int c = 0; c < 3; ++c) coordinates_[3 * i + c] = points[order_[i]][c];
  }

  // Searched below `bound` (squared; max: no bound), the nearest point is the unbounded search's
  // whenever it lies below the bound: both searches find the first leaf holding a point at the
  // least distance, the bounded one in fewer visits. -1 when no point lies below the bound.
  int nearest(const Vec3& query, double* squared_distance,
              double bound = std::numeric_limits<double>::max()) const {
    const double q[3] = {query.x(), query.y(), query.z()};
    const bool bounded = bound < std::numeric_limits<double>::max();
    Candidate best{bound, bounded ? -1 : 0};
    search(0, q, best);
    if (squared_distance) *squared_distance = best.distance;
    return best.index;
  }

 private:
  struct Node {
    int axis = -1;      // split dimension; -1 for a leaf
    int first = 0;      // leaf: positions [first, last) of order_ and coordinates_
    int last = 0;       // inner node: `last` is the second child (the first follows the node)
    double low = 0.0;   // inner node: upper bound of the first child along `axis` ...
    double high = 0.0;  // ... and lower bound of the second
    Box box;            // bounds of the node's points
  };
  struct Candidate {
    double distance;
    int index;
  };

  // FLANN's divideTree: returns the node of order_[left, right) and leaves its bounding box in
  // `box`.
  int divide(const std::vector<Vec3>& points, int left, int right, Box& box) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    if (right - left <= kLeafSize) {
      nodes_[id].first = left;
      nodes_[id].last = right;
      for (int c = 0; c < 3; ++c) box[c] = {points[order_[left]][c], points[order_[left]][c]};
      for (int k = left + 1; k < right; ++k)
        for (int c = 0; c < 3; ++c) {
          if (box[c].low > points[order_[k]][c]) box[c].low = points[order_[k]][c];
          if (box[c].high < points[order_[k]][c]) box[c].high = points[order_[k]][c];
        }
      nodes_[id].box = box;
      return id;
    }
    int index, axis;
    double cut;
    middle_split(points, order_.data() + left, right - left, index, axis, cut, box);
    Box left_box = box;
    left_box[axis].high = cut;
    divide(points, left, left + index, left_box);
    Box right_box = box;
    right_box[axis].low = cut;
    const int second = divide(points, left + index, right, right_box);
    nodes_[id].axis = axis;
    nodes_[id].last = second;
    nodes_[id].low = left_box[axis].high;
    nodes_[id].high = right_box[axis].low;
    for (int c = 0; c < 3; ++c) {
      box[c].low = std::min(left_box[c].low, right_box[c].low);
      box[c].high = std::max(left_box[c].high, right_box[c].high);
    }
    nodes_[id].box = box;
    return id;
  }

  static void min_max(const std::vector<Vec3>& points, const int* ind, int count, int axis,
                      double& low, double& high) {
    low = high = points[ind[0]][axis];
    for (int i = 1; i < count; ++i) {
      const double value = points[ind[i]][axis];
      if (value < low) low = value;
      if (value > high) high = value;
    }
  }

  // FLANN's middleSplit: cut the widest dimension of the points at its middle.
  static void middle_split(const std::vector<Vec3>& points, int* ind, int count, int& index,
                           int& axis, double& cut, const Box& box) {
    double max_span = box[0].high - box[0].low;
    axis = 0;
    for (int c = 1; c < 3; ++c) {
      const double span = box[c].high - box[c].low;
      if (span > max_span) {
        max_span = span;
        axis = c;
      }
    }
    double low, high;
    min_max(points, ind, count, axis, low, high);
    cut = (low + high) / 2;
    max_span = high - low;
    const int first_axis = axis;
    for (int c = 0; c < 3; ++c) {
      if (c == first_axis || !(box[c].high - box[c].low > max_span)) continue;
      min_max(points, ind, count, c, low, high);
      if (high - low > max_span) {
        max_span = high - low;
        axis = c;
        cut = (low + high) / 2;
      }
    }
    int lim1, lim2;
    plane_split(points, ind, count, axis, cut, lim1, lim2);
    if (lim1 > count / 2)
      index = lim1;
    else if (lim2 < count / 2)
      index = lim2;
    else
      index = count / 2;
  }

  // FLANN's planeSplit: reorders ind so that values < cut come first, then == cut, then > cut.
  static void plane_split(const std::vector<Vec3>& points, int* ind, int count, int axis,
                          double cut, int& lim1, int& lim2) {
    int left = 0;
    int right = count - 1;
    for (;;) {
      while (left <= right && points[ind[left]][axis] < cut) ++left;
      while (left <= right && points[ind[right]][axis] >= cut) --right;
      if (left > right) break;
      std::swap(ind[left], ind[right]);
      ++left;
      --right;
    }
    lim1 = left;
    right = count - 1;
    for (;;) {
      while (left <= right && points[ind[left]][axis] <= cut) ++left;
      while (left <= right && points[ind[right]][axis] > cut) --right;
      if (left > right) break;
      std::swap(ind[left], ind[right]);
      ++left;
      --right;
    }
    lim2 = left;
  }

  // Squared distance from q to the box, summed like a point's.
  static double box_distance(const Box& box, const double* q) {
    double gap[3];
    for (int c = 0; c < 3; ++c)
      gap[c] =
          q[c] < box[c].low ? q[c] - box[c].low : (q[c] > box[c].high ? q[c] - box[c].high : 0.0);
    return gap[0] * gap[0] + gap[1] * gap[1] + gap[2] * gap[2];
  }

  // A leaf only takes points closer than the best distance at entry, and of those the closest,
  // then the lowest index (as FLANN's leaf and its single-result set).
  void search(int id, const double* q, Candidate& best) const {
    const Node& node = nodes_[id];
    if (node.axis < 0) {
      const double worst = best.distance;
      for (int i = node.first; i < node.last; ++i) {
        const double* point = &coordinates_[3 * i];
        const double dx = q[0] - point[0];
        const double dy = q[1] - point[1];
        const double dz = q[2] - point[2];
        const double distance = dx * dx + dy * dy + dz * dz;
        if (distance < worst &&
            (distance < best.distance || (distance == best.distance && order_[i] < best.index)))
          best = {distance, order_[i]};
      }
      return;
    }
    const double value = q[node.axis];
    int near = id + 1;
    int far = node.last;
    if (!((value - node.low) + (value - node.high) < 0)) std::swap(near, far);
    // The near child is searched whatever its box: a child that cannot hold a point as near as
    // the best has no point a leaf would take, so a search of it changes nothing but the time.
    search(near, q, best);
    if (box_distance(nodes_[far].box, q) <= best.distance) search(far, q, best);
  }

  std::vector<int> order_;
  std::vector<double> coordinates_;  // points in leaf order
  std::vector<Node> nodes_;
};

}  // namespace

// Each of the two trees is built when first asked for: most users ask only for the nearest
// point (the shrinking ball) or only for k nearest (noise, normals, areas), and a build costs
// about as much as a few thousand queries.
struct KdTree::Impl {
  std::vector<double> coordinates;  // x y z of each point; FLANN keeps a view into this buffer
  std::once_flag index_built, nearest_built;
  std::unique_ptr<flann::KDTreeSingleIndex<flann::L2_Simple<double>>> index;
  std::unique_ptr<NearestTree> nearest;

  const flann::KDTreeSingleIndex<flann::L2_Simple<double>>& flann_index() {
    std::call_once(index_built, [this] {
      flann::Matrix<double> data(coordinates.data(), coordinates.size() / 3, 3);
      index = std::make_unique<flann::KDTreeSingleIndex<flann::L2_Simple<double>>>(
          data, flann::KDTreeSingleIndexParams(kLeafSize));
      index->buildIndex();
    });
    return *index;
  }

  const NearestTree& nearest_tree() {
    std::call_once(nearest_built, [this] {
      std::vector<Vec3> points(coordinates.size() / 3);
      for (std::size_t i = 0; i < points.size(); ++i)
        points[i] = Vec3(coordinates[3 * i], coordinates[3 * i + 1], coordinates[3 * i + 2]);
      nearest = std::make_unique<NearestTree>(points);
    });
    return *nearest;
  }
};

KdTree::KdTree(const std::vector<Vec3>& points)
    : impl_(std::make_unique<Impl>()), count_(points.size()) {
  if (points.empty()) throw InvalidInput("cannot build a KD-tree over an empty point set");
  impl_->coordinates.resize(3 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int c = 0; c < 3; ++c) impl_->coordinates[3 * i + c] = points[i][c];
}

KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

int KdTree::nearest(const Vec3& query, double* squared_distance) const {
  return impl_->nearest_tree().nearest(query, squared_distance);
}

int KdTree::nearest_within(const Vec3& query, double squared_bound,
                           double* squared_distance) const {
  return impl_->nearest_tree().nearest(query, squared_distance, squared_bound);
}

void KdTree::k_nearest(const Vec3& query, int k, std::vector<int>& indices,
                       std::vector<double>& squared_distances) const {
  const int wanted = std::min<int>(k, static_cast<int>(count_));
  indices.assign(wanted, -1);
  squared_distances.assign(wanted, 0.0);
  const double q[3] = {query.x(), query.y(), query.z()};
  flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED);
  params.sorted = true;
  std::vector<std::size_t> found(wanted);
  const std::size_t n = flann_query::k_nearest(impl_->flann_index(), q, found.size(), found.data(),
                                               squared_distances.data(), params);
  for (std::size_t i = 0; i < n; ++i) indices[i] = static_cast<int>(found[i]);
}

double median_spacing(const KdTree& tree, const std::vector<Vec3>& points, int stride) {
  if (points.size() < 2) return 0.0;
  std::vector<double> spacings;
  std::vector<int> indices;
  std::vector<double> squared_distances;
  for (std::size_t i = 0; i < points.size(); i += static_cast<std::size_t>(stride)) {
    tree.k_nearest(points[i], 2, indices, squared_distances);
    spacings.push_back(std::sqrt(squared_distances.back()));
  }
  return median(spacings);
}

}  // namespace vmas
