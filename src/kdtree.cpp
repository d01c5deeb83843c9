#include "vmas/kdtree.hpp"

#include <flann/flann.hpp>
#include <limits>

#include "vmas/error.hpp"

namespace vmas {

struct KdTree::Impl {
  std::vector<double> coordinates;  // FLANN keeps a view into this buffer
  std::unique_ptr<flann::KDTreeSingleIndex<flann::L2_Simple<double>>> index;
};

KdTree::KdTree(const std::vector<Vec3>& points) : impl_(std::make_unique<Impl>()), count_(points.size()) {
  if (points.empty()) throw InvalidInput("cannot build a KD-tree over an empty point set");
  impl_->coordinates.resize(3 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int c = 0; c < 3; ++c) impl_->coordinates[3 * i + c] = points[i][c];
  flann::Matrix<double> data(impl_->coordinates.data(), points.size(), 3);
  impl_->index = std::make_unique<flann::KDTreeSingleIndex<flann::L2_Simple<double>>>(
      data, flann::KDTreeSingleIndexParams(10));
  impl_->index->buildIndex();
}

KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

namespace {

// The single nearest neighbour without the allocations of FLANN's general k-NN path: this query
// runs in the inner loop of the shrinking ball.
class NearestResult : public flann::ResultSet<double> {
 public:
  bool full() const override { return true; }
  void addPoint(double distance, size_t index) override {
    if (distance < distance_ || (distance == distance_ && index < index_)) {
      distance_ = distance;
      index_ = index;
    }
  }
  double worstDist() const override { return distance_; }
  double distance() const { return distance_; }
  size_t index() const { return index_; }

 private:
  double distance_ = std::numeric_limits<double>::max();
  size_t index_ = 0;
};

}  // namespace

int KdTree::nearest(const Vec3& query, double* squared_distance) const {
  NearestResult result;
  const double q[3] = {query.x(), query.y(), query.z()};
  impl_->index->findNeighbors(result, q, flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED));
  if (squared_distance) *squared_distance = result.distance();
  return static_cast<int>(result.index());
}

void KdTree::k_nearest(const Vec3& query, int k, std::vector<int>& indices,
                       std::vector<double>& squared_distances) const {
  const int wanted = std::min<int>(k, static_cast<int>(count_));
  indices.assign(wanted, -1);
  squared_distances.assign(wanted, 0.0);
  double q[3] = {query.x(), query.y(), query.z()};
  flann::Matrix<double> query_matrix(q, 1, 3);
  flann::Matrix<int> index_matrix(indices.data(), 1, wanted);
  flann::Matrix<double> distance_matrix(squared_distances.data(), 1, wanted);
  flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED);
  params.sorted = true;
  impl_->index->knnSearch(query_matrix, index_matrix, distance_matrix, wanted, params);
}

}  // namespace vmas
