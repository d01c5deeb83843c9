#include "prepare/denoise.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <stdexcept>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <utility>

#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/mls.h>
// PCL's template sources, so that the classes used here are compiled into vmas: of PCL's
// libraries only libpcl_common is linked (libpcl_surface pulls VTK in, and the filters, search
// and kdtree libraries would slow every start of vmas with their relocations).
#include <pcl/filters/impl/voxel_grid.hpp>
#include <pcl/impl/pcl_base.hpp>
#include <pcl/kdtree/impl/kdtree_flann.hpp>
#include <pcl/search/impl/kdtree.hpp>
#include <pcl/search/impl/organized.hpp>
#include <pcl/search/impl/search.hpp>
#include <pcl/surface/impl/mls.hpp>

#include "core/cloud_graph.hpp"
#include "core/disjoint_sets.hpp"
#include "core/flann_query.hpp"
#include "core/quadric_fit.hpp"
#include "vmas/error.hpp"
#include "vmas/kdtree.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif


namespace vmas {
namespace {

// Median of |x| for a standard normal x: a robust deviation is a median distance over this.
constexpr double kHalfNormalMedian = 0.6745;
// restore_smoothing_bias: residuals are averaged over the points within this fraction of the
// smoothing's support radius, ...
constexpr double kBiasRadiusInSupports = 0.5;
// ... at least this many (their noise falls to a tenth), of an even subset of every
// (n / this)-th point (8 000 to 16 000 points; all below 16 000).
constexpr std::size_t kBiasNeighbours = 128, kBiasReferencePoints = 8000;
// ... and a point takes a blend of the figures of this many nearest of the subset.
constexpr std::size_t kBiasBlended = 4;
// supported_by_noise: a smoothed point is measured against the points within this many support
// radii: far enough to reach from the fringe past an edge to the surface inside it ...
constexpr double kFringeReach = 3.0;
// ... whose support is this quantile of theirs (the fringe itself is among them) ...
constexpr double kFringeReference = 0.75;
// ... among at most about this many points spread evenly through the cloud ...
constexpr std::size_t kFringeReferencePoints = 4000;
// ... and it is fringe below this fraction of that: past about half a deviation beyond an edge,
// where a sampling smeared by Gaussian noise falls below a third of its density inside. (On the
// benchmark's noisy clouds, 0.2-0.3 gave the same results within their spread; 0.3 the least
// mean ε.)
constexpr double kFringeDensity = 0.3;

// pcl::search::KdTree's answers without FLANN's region per query (flann_query.hpp): the same
// FLANN tree as pcl::KdTreeFLANN builds (single KD-tree, 15 points per leaf, float coordinates),
// so the same neighbours. Dense clouds only (vmas's never hold NaN points); no indices.
class FlannSearch : public pcl::search::Search<pcl::PointXYZ> {
 public:
  using Index = ::flann::KDTreeSingleIndex<::flann::L2_Simple<float>>;
  explicit FlannSearch(bool sorted) : pcl::search::Search<pcl::PointXYZ>("FlannSearch", sorted) {}

  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override {
    if (indices) throw InvalidArgument("FlannSearch: indices are not supported");
    input_ = cloud;
    coordinates_.resize(3 * cloud->size());
    for (std::size_t i = 0; i < cloud->size(); ++i)
      std::copy_n((*cloud)[i].data, 3, coordinates_.begin() + 3 * i);
    index_ = std::make_unique<Index>(::flann::Matrix<float>(coordinates_.data(), cloud->size(), 3),
                                     ::flann::KDTreeSingleIndexParams(15));
    index_->buildIndex();
  }

  // As pcl::KdTreeFLANN::nearestKSearch (results always sorted).
  int nearestKSearch(const pcl::PointXYZ& point, int k, pcl::Indices& indices,
                     std::vector<float>& squared_distances) const override {
    const std::size_t wanted = std::min<std::size_t>(k, input_->size());
    indices.resize(wanted);
    squared_distances.resize(wanted);
    std::vector<std::size_t> found(wanted);
    if (wanted > 0)
      flann_query::k_nearest(*index_, point.data, wanted, found.data(), squared_distances.data(),
                             ::flann::SearchParams(-1, 0.0f));
    std::copy(found.begin(), found.end(), indices.begin());
    return static_cast<int>(wanted);
  }

  // As pcl::KdTreeFLANN::radiusSearch (sorted as the constructor says).
  int radiusSearch(const pcl::PointXYZ& point, double radius, pcl::Indices& indices,
                   std::vector<float>& squared_distances, unsigned int max_nn = 0) const override {
    std::vector<std::size_t> found;
    const std::size_t count =
        flann_query::within_radius(*index_, point.data, static_cast<float>(radius * radius),
                                   max_nn >= input_->size() ? 0 : max_nn, found, squared_distances,
                                   ::flann::SearchParams(-1, 0.0f, sorted_results_));
    indices.assign(found.begin(), found.end());
    return static_cast<int>(count);
  }

 private:
  std::vector<float> coordinates_;  // FLANN keeps a view into this buffer
  std::unique_ptr<Index> index_;
};

// The inliers among `candidates` by pcl::StatisticalOutlierRemoval's rule, computed as it does
// (float distances, the same sums), but with the searcher above: the filter keeps its own
// searcher private. A point whose mean distance to its k nearest neighbours in the whole cloud
// exceeds the mean of those by `deviations` standard deviations is an outlier.
std::vector<int> statistical_inliers(const FlannSearch& search,
                                     const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                     const std::vector<int>& candidates, int k, double deviations) {
  const int searched = k + 1;  // the point itself comes first
  std::vector<float> mean_distance(candidates.size(), 0.0f);
  const auto count = static_cast<std::ptrdiff_t>(candidates.size());
  int measured = 0;
#pragma omp parallel reduction(+ : measured)
  {
    pcl::Indices neighbours(searched);
    std::vector<float> squared(searched);
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      if (search.nearestKSearch(cloud[candidates[i]], searched, neighbours, squared) == 0) continue;
      double sum = 0.0;
      for (int j = 1; j < searched; ++j) sum += std::sqrt(squared[j]);
      mean_distance[i] = static_cast<float>(sum / k);
      ++measured;
    }
  }
  double sum = 0.0, squares = 0.0;
  for (float d : mean_distance) {
    sum += d;
    squares += d * d;  // in float, as PCL does
  }
  const double mean = sum / measured;
  const double deviation = std::sqrt((squares - sum * sum / measured) / (measured - 1.0));
  const double threshold = mean + deviations * deviation;
  std::vector<int> inliers;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (!(mean_distance[i] > threshold)) inliers.push_back(candidates[i]);
  return inliers;
}

// RMS distance of `points[indices]` to their quadric (fit_quadric), with the six fitted
// coefficients taken out of the degrees of freedom. NaN when the neighbourhood is degenerate.
double quadric_residual(const std::vector<Vec3>& points, const std::vector<int>& indices) {
  const internal::QuadricFit quadric = internal::fit_quadric(points, indices);
  if (!quadric.valid) return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(quadric.residual_squares / (static_cast<double>(indices.size()) - 6.0));
}

// Points moved by -centroid, in float: PCL computes in float, and large coordinates (far from
// the origin) would lose their precision otherwise.
pcl::PointCloud<pcl::PointXYZ>::Ptr cloud_about(const std::vector<Vec3>& points,
                                                const Vec3& centroid) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f p = (points[i] - centroid).cast<float>();
    (*cloud)[i] = pcl::PointXYZ(p.x(), p.y(), p.z());
  }
  return cloud;
}

// cloud_about the points' own centroid.
pcl::PointCloud<pcl::PointXYZ>::Ptr centred_cloud(const std::vector<Vec3>& points, Vec3& centroid) {
  centroid = Vec3::Zero();
  for (const Vec3& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  return cloud_about(points, centroid);
}

}  // namespace

NoiseEstimate estimate_noise(const std::vector<Vec3>& points) {
  constexpr int kMaxNeighbours = 2048;
  constexpr double kRadiusInResiduals = 3.0;
  // The noise of a point does not depend on how many others there are: the fits run on an even
  // subset, so that big clouds cost no more and need no bigger neighbourhoods.
  constexpr int kSubset = 10'000;
  // Query points: enough for a stable median, fewer for the large neighbourhoods.
  constexpr long kQueryNeighbours = 500'000, kMinQueries = 500, kMaxQueries = 4000;
  const int count = static_cast<int>(points.size());
  if (count < kFewestNoiseNeighbours)
    throw InvalidInput("too few points (" + std::to_string(count) + ") to estimate the noise");
  NoiseEstimate estimate;
  const KdTree tree(points);
  std::vector<double> spacings;
  std::vector<int> indices;
  std::vector<double> squared_distances;
  for (int i = 0; i < count; i += std::max(1, count / kSubset)) {
    tree.k_nearest(points[i], 2, indices, squared_distances);
    spacings.push_back(std::sqrt(squared_distances.back()));
  }
  estimate.spacing = median(spacings);

  std::vector<Vec3> subset;
  for (int i = 0; i < count; i += std::max(1, count / kSubset)) subset.push_back(points[i]);
  const int subset_count = static_cast<int>(subset.size());
  const KdTree subset_tree(subset);
  for (int k = kFewestNoiseNeighbours; k <= kMaxNeighbours; k *= 2) {
    const int width = std::min(k, subset_count);
    const long queries_wanted = std::clamp(kQueryNeighbours / width, kMinQueries, kMaxQueries);
    const int stride = std::max<long>(1, subset_count / queries_wanted);
    std::vector<int> queries;
    for (int i = 0; i < subset_count; i += stride) queries.push_back(i);
    const int query_count = static_cast<int>(queries.size());
    std::vector<double> residuals(query_count), radii(query_count);
#pragma omp parallel
    {
      std::vector<int> neighbours;
      std::vector<double> distances;
#pragma omp for schedule(static)
      for (int q = 0; q < query_count; ++q) {
        subset_tree.k_nearest(subset[queries[q]], width, neighbours, distances);
        residuals[q] = quadric_residual(subset, neighbours);
        radii[q] = std::sqrt(distances.back());
      }
    }
    residuals.erase(std::remove_if(residuals.begin(), residuals.end(),
                                   [](double r) { return !std::isfinite(r); }),
                    residuals.end());
    estimate.sigma = median(residuals);
    estimate.neighbours = width;
    if (median(radii) >= kRadiusInResiduals * estimate.sigma || width == subset_count) break;
  }
  return estimate;
}

void DenoiseOptions::validate() const {
  if (!(clean_fraction_of_spacing >= 0.0 && clean_fraction_of_spacing <= 100.0))
    throw InvalidOption("clean_fraction_of_spacing", "must be in [0, 100]");
  if (!(mls_radius_in_sigmas > 0.0 && mls_radius_in_sigmas <= 100.0))
    throw InvalidOption("mls_radius_in_sigmas", "must be in (0, 100] smoothing scales");
  if (outlier_k < 2 || outlier_k > 200)
    throw InvalidOption("outlier_k",
                        "must be between 2 and 200 (got " + std::to_string(outlier_k) + ")");
  if (!(outlier_deviations > 0.0)) throw InvalidOption("outlier_deviations", "must be positive");
}

bool is_noisy(const NoiseEstimate& noise, const DenoiseOptions& options) {
  return noise.sigma > options.clean_fraction_of_spacing * noise.spacing;
}

std::vector<int> inlier_indices(const std::vector<Vec3>& points, const DenoiseOptions& options) {
  options.validate();
  // Gross outliers inflate the deviation of the neighbour distances that the filter measures
  // them against, so that those nearer the surface survive a pass; passes repeat while they
  // remove a noticeable share. A clean cloud stops after one. A first pass that flags a large
  // share has found uneven density, not strays (the merged bunny scan: 3 %, its sparse parts;
  // dropping them cost 0.5 points of ε): the cloud is kept whole.
  constexpr int kMaxPasses = 4;
  constexpr double kNoticeable = 0.005, kLarge = 0.02;
  std::vector<int> kept(points.size());
  std::iota(kept.begin(), kept.end(), 0);
  Vec3 centroid;
  auto cloud = centred_cloud(points, centroid);
  FlannSearch search(false);
  search.setInputCloud(cloud);
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    if (static_cast<int>(kept.size()) <= 2 * options.outlier_k) break;
    const std::vector<int> inliers =
        statistical_inliers(search, *cloud, kept, options.outlier_k, options.outlier_deviations);
    const std::size_t removed = kept.size() - inliers.size();
    kept = inliers;
    const double share = static_cast<double>(removed) / static_cast<double>(points.size());
    if (pass == 0 && share > kLarge) {
      kept.resize(points.size());
      std::iota(kept.begin(), kept.end(), 0);
      break;
    }
    if (share < kNoticeable || share > kLarge) break;
  }
  return kept;
}

namespace {

// A flagged point stays when it continues the sampling of its nearest neighbour j that is kept,
// only more sparsely: within kNearReach × m_j (j's mean distance to its neighbours), or within
// kFarReach × m_j and kOffPlane × m_j of the surface through j's neighbourhood (its quadric: at
// a curved tip a plane would leave the sampling's own sparse points off it). A stray's nearest
// kept point is the surface below it, and it lies off that surface.
constexpr double kNearReach = 1.0, kFarReach = 2.0, kOffPlane = 0.3;
// A sparse part is kept from its edge inwards (its inner points may have only flagged
// neighbours), for at most this many rounds; strays lie several spacings apart and never
// continue one another.
constexpr int kSparseRounds = 8;
// In a clean sampling nearly every flagged point continues it (at least 97 % on 48 clean clouds
// of 2 000-50 000 points); in one with scattered strays most do not (at most 28 % with 1 %
// uniform strays), and the few that do are strays near the surface as often as sparse parts:
// there a flagged point stays only when it lies on the quadric, however near (a thin tip's few
// points, which the vessel with 1 % strays lost: ε 1.08 % against 0.64 %).
constexpr double kScatteredShare = 0.5;

}  // namespace

std::vector<int> with_sparse_parts(const std::vector<Vec3>& points, const std::vector<int>& inliers,
                                   const DenoiseOptions& options) {
  options.validate();
  const int count = static_cast<int>(points.size());
  const int k = options.outlier_k;
  if (inliers.size() == points.size() || count <= k) return inliers;
  const KdTree tree(points);
  // A point's k nearest others, looked up once and only for the points the rule needs.
  std::vector<std::vector<int>> neighbours(count);
  std::vector<double> squared;
  const auto neighbours_of = [&](int p) -> const std::vector<int>& {
    if (neighbours[p].empty()) {
      tree.k_nearest(points[p], k + 1, neighbours[p], squared);
      neighbours[p].erase(neighbours[p].begin());  // the point itself
    }
    return neighbours[p];
  };
  // Spacing of the sampling a point belongs to: its own mean neighbour distance if it is kept,
  // that of the point it continues if it is kept as sparse; NaN while it is flagged.
  std::vector<double> spacing(count, std::numeric_limits<double>::quiet_NaN());
  std::vector<char> kept(count, 0);
  for (int i : inliers) kept[i] = 1;
  const auto spacing_of = [&](int j) {
    if (kept[j] && std::isnan(spacing[j])) {
      double sum = 0.0;
      for (int n : neighbours_of(j)) sum += (points[n] - points[j]).norm();
      spacing[j] = sum / k;
    }
    return spacing[j];
  };
  // `on_surface_only`: a flagged point near its kept neighbour must lie on the quadric too.
  const auto continues = [&](int p, int j, double reach, bool on_surface_only) {
    const double gap = (points[p] - points[j]).norm();
    if (gap <= kNearReach * reach && !on_surface_only) return true;
    if (gap > kFarReach * reach) return false;
    std::vector<int> around = neighbours_of(j);
    around.push_back(j);
    const internal::QuadricFit surface = internal::fit_quadric(points, around);
    return surface.valid && surface.offset(points[p]) <= kOffPlane * reach;
  };
  const auto grow = [&](bool on_surface_only) {
    for (int p = 0; p < count; ++p)
      if (!kept[p]) spacing[p] = std::numeric_limits<double>::quiet_NaN();
    std::vector<int> grown_points = inliers;
    for (int round = 0; round < kSparseRounds; ++round) {
      bool grown = false;
      for (int p = 0; p < count; ++p) {
        if (kept[p] || !std::isnan(spacing[p])) continue;
        for (int j : neighbours_of(p)) {
          const double reach = spacing_of(j);
          if (std::isnan(reach)) continue;  // flagged too: the next nearest
          if (continues(p, j, reach, on_surface_only)) {
            spacing[p] = reach;
            grown_points.push_back(p);
            grown = true;
          }
          break;  // only the nearest point that is not flagged counts
        }
      }
      if (!grown) break;
    }
    return grown_points;
  };
  std::vector<int> result = grow(false);
  const std::size_t flagged = points.size() - inliers.size();
  const std::size_t continuing = result.size() - inliers.size();
  if (static_cast<double>(flagged - continuing) > kScatteredShare * static_cast<double>(flagged))
    result = grow(true);
  std::sort(result.begin(), result.end());
  return result;
}

namespace {

// PCL's MovingLeastSquares surfaces of a cloud with support `radius`, fitted on a voxel grid's
// centroids (a bounded number of samples per fit whatever the density, and the voxel averages are
// already less noisy). A point goes onto the surface fitted at its nearest centroid.
class MlsSurfaces {
 public:
  // Fits at every centroid, or only at those nearest to points[i] for i in `only` when given:
  // each fit depends on its neighbourhood alone, so those are the fits of the whole surface.
  MlsSurfaces(const std::vector<Vec3>& points, double radius, const std::vector<int>* only) {
    if (!(radius > 0.0)) throw std::logic_error("MlsSurfaces: the radius must be positive");
    constexpr double kFitsPerRadius = 6.0;        // voxel size of the fitting cloud: radius / this
    constexpr double kMaxVoxelsPerAxis = 1000.0;  // keeps VoxelGrid's integer keys from overflowing
    const auto cloud = centred_cloud(points, centroid_);
    const Box box = bounding_box(points);
    const float voxel = static_cast<float>(
        std::max(radius / kFitsPerRadius, box.sizes().maxCoeff() / kMaxVoxelsPerAxis));
    pcl::VoxelGrid<pcl::PointXYZ> grid;
    grid.setInputCloud(cloud);
    grid.setLeafSize(voxel, voxel, voxel);
    auto fitting = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    grid.filter(*fitting);
    std::vector<Vec3> fitting_points(fitting->size());
    for (std::size_t i = 0; i < fitting->size(); ++i)
      fitting_points[i] = (*fitting)[i].getVector3fMap().cast<double>();
    tree_.emplace(fitting_points);

    mls_.setInputCloud(fitting);
    if (only) {
      auto nearest = std::make_shared<pcl::Indices>();
      for (int i : *only) nearest->push_back(tree_->nearest(points[i] - centroid_));
      std::sort(nearest->begin(), nearest->end());
      nearest->erase(std::unique(nearest->begin(), nearest->end()), nearest->end());
      mls_.setIndices(nearest);
    }
    mls_.setSearchMethod(std::make_shared<FlannSearch>(true));
    mls_.setSearchRadius(radius);
    mls_.setPolynomialOrder(2);
    mls_.setCacheMLSResults(true);
#ifdef _OPENMP
    mls_.setNumberOfThreads(static_cast<unsigned>(omp_get_max_threads()));
#endif
    pcl::PointCloud<pcl::PointNormal> fitted;
    mls_.process(fitted);
  }

  // `point` moved onto its surface, and the surface normal there; false when no valid fit.
  bool project(const Vec3& point, Vec3& projected, Vec3& normal) const {
    constexpr int kPolynomialCoefficients = 6;  // order 2
    const Vec3 local = point - centroid_;
    const pcl::MLSResult& fit = mls_.getMLSResults()[tree_->nearest(local)];
    if (!fit.valid) return false;
    const pcl::MLSResult::MLSProjectionResults on =
        fit.projectPoint(local, pcl::MLSResult::SIMPLE, kPolynomialCoefficients);
    if (!on.point.allFinite() || !on.normal.allFinite()) return false;
    projected = on.point + centroid_;
    normal = on.normal;
    return true;
  }

 private:
  Vec3 centroid_;
  std::optional<KdTree> tree_;  // over the fitting centroids (centred)
  pcl::MovingLeastSquares<pcl::PointXYZ, pcl::PointNormal> mls_;  // holds the fits
};

}  // namespace

std::vector<Vec3> smooth_mls(std::vector<Vec3>& points, double radius) {
  const MlsSurfaces surfaces(points, radius, nullptr);
  std::vector<Vec3> normals(points.size(),
                            Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
  const int count = static_cast<int>(points.size());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < count; ++i) {
    Vec3 projected, normal;
    if (!surfaces.project(points[i], projected, normal)) continue;
    points[i] = projected;
    normals[i] = normal;
  }
  return normals;
}

namespace {

// The pieces that the kept points form with the points activated so far (kept ones first).
class KeptPieces {
 public:
  KeptPieces(const std::vector<std::vector<int>>& adjacent, const std::vector<char>& kept)
      : adjacent_(adjacent), active_(kept.size(), 0), sets_(static_cast<int>(kept.size())),
        holds_kept_(kept.begin(), kept.end()) {
    for (std::size_t v = 0; v < kept.size(); ++v)
      if (kept[v]) {
        ++count_;
        activate(static_cast<int>(v));
      }
  }
  void activate(int v) {
    active_[v] = 1;
    for (int w : adjacent_[v]) {
      if (!active_[w]) continue;
      const int a = sets_.find(v), b = sets_.find(w);
      if (a == b) continue;
      const bool both = holds_kept_[a] && holds_kept_[b];
      const char either = holds_kept_[a] || holds_kept_[b];
      sets_.unite(a, b);
      holds_kept_[sets_.find(a)] = either;
      count_ -= both;
    }
  }
  int count() const { return count_; }

 private:
  const std::vector<std::vector<int>>& adjacent_;
  std::vector<char> active_;
  internal::DisjointSets sets_;
  std::vector<char> holds_kept_;  // per set root
  int count_ = 0;
};

// Rejoins what a trim (`kept`, one flag per point of `neighbours`) cut in pieces: a thin part whose
// noise leaves its points little support. Of the groups of dropped points that touch two or more
// pieces of the kept ones, the best supported points come back one by one until the pieces are
// joined as the whole groups would join them; the rest of the trim stands.
void rejoin_pieces(const internal::Neighbourhoods& neighbours, const std::vector<int>& support,
                   std::vector<char>& kept) {
  const int n = static_cast<int>(kept.size());
  // Both directions of the k-nearest relation: a point joins whoever lists it too.
  std::vector<std::vector<int>> adjacent(n);
  for (int v = 0; v < n; ++v)
    for (int i = 0; i < neighbours.width; ++i) {
      const int w = neighbours.row(v)[i];
      if (w == v) continue;
      adjacent[v].push_back(w);
      adjacent[w].push_back(v);
    }
  // Pieces of the kept points and groups of the dropped ones; a group's pieces: -1 none yet,
  // -2 two or more.
  internal::DisjointSets sides(n);
  for (int v = 0; v < n; ++v)
    for (int w : adjacent[v])
      if (kept[v] == kept[w]) sides.unite(v, w);
  std::vector<int> piece_of_group(n, -1);
  for (int v = 0; v < n; ++v)
    if (!kept[v])
      for (int w : adjacent[v]) {
        if (!kept[w]) continue;
        int& piece = piece_of_group[sides.find(v)];
        const int touched = sides.find(w);
        piece = piece == -1 || piece == touched ? touched : -2;
      }
  std::vector<int> candidates;
  for (int v = 0; v < n; ++v)
    if (!kept[v] && piece_of_group[sides.find(v)] == -2) candidates.push_back(v);
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&](int a, int b) { return support[a] > support[b]; });
  // As far as the whole groups would join the pieces (each of them touches kept points), the
  // best supported of them, one by one.
  std::vector<char> with_groups = kept;
  for (int v : candidates) with_groups[v] = 1;
  const int joinable = internal::joined_pieces(neighbours, &with_groups);
  KeptPieces pieces(adjacent, kept);
  for (int v : candidates) {
    if (pieces.count() <= joinable) break;
    pieces.activate(v);
    kept[v] = 1;
  }
}

}  // namespace

std::vector<int> supported_by_noise(const std::vector<Vec3>& smoothed, const std::vector<Vec3>& raw,
                                    double radius) {
  std::vector<int> all(smoothed.size());
  std::iota(all.begin(), all.end(), 0);
  if (smoothed.empty() || raw.empty() || !(radius > 0.0)) return all;
  Vec3 centroid;
  const auto raw_cloud = centred_cloud(raw, centroid);
  FlannSearch raw_search(false);
  raw_search.setInputCloud(raw_cloud);
  const auto smoothed_cloud = cloud_about(smoothed, centroid);
  FlannSearch smoothed_search(false);
  smoothed_search.setInputCloud(smoothed_cloud);
  // The points compared with: an even subset (a quantile of a few dozen counts is as good as of
  // hundreds, and the search over all of them within 3 radii took as long as the smoothing).
  const std::size_t stride = std::max<std::size_t>(1, smoothed.size() / kFringeReferencePoints);
  auto reference_cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (std::size_t i = 0; i < smoothed.size(); i += stride)
    reference_cloud->push_back((*smoothed_cloud)[i]);
  FlannSearch reference_search(false);
  reference_search.setInputCloud(reference_cloud);
  const auto count = static_cast<std::ptrdiff_t>(smoothed.size());
  const double reach = kFringeReach * radius;
  std::vector<int> support(smoothed.size(), 0);
#pragma omp parallel
  {
    pcl::Indices found;
    std::vector<float> squared;
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i)
      support[i] = raw_search.radiusSearch((*smoothed_cloud)[i], radius, found, squared);
  }
  std::vector<char> kept(smoothed.size(), 1);
#pragma omp parallel
  {
    pcl::Indices around;
    std::vector<float> squared;
    std::vector<int> counts;
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      counts.clear();
      reference_search.radiusSearch((*smoothed_cloud)[i], reach, around, squared);
      for (int r : around)
        if (r * stride != static_cast<std::size_t>(i)) counts.push_back(support[r * stride]);
      if (counts.empty()) {  // too few nearby for the subset: all of them
        smoothed_search.radiusSearch((*smoothed_cloud)[i], reach, around, squared);
        for (int j : around)
          if (j != i) counts.push_back(support[j]);
      }
      // Alone that far from the rest of the smoothed surface: a stray.
      if (counts.empty()) {
        kept[i] = 0;
        continue;
      }
      const auto at = static_cast<std::size_t>(kFringeReference * (counts.size() - 1));
      std::nth_element(counts.begin(), counts.begin() + at, counts.end());
      kept[i] = support[i] >= kFringeDensity * counts[at];
    }
  }
  const auto kept_points = [&] {
    std::vector<Vec3> trimmed;
    for (std::size_t i = 0; i < smoothed.size(); ++i)
      if (kept[i]) trimmed.push_back(smoothed[i]);
    return trimmed;
  };
  // A trim that leaves the data in more pieces went through a thin part, not along an edge.
  if (std::find(kept.begin(), kept.end(), 0) != kept.end()) {
    const internal::Neighbourhoods neighbours =
        internal::k_nearest_all(smoothed, internal::kJoiningNeighbours);
    const int pieces = internal::joined_pieces(neighbours);
    // The kept points' own graph; only when the rows of all the points, which bound its pieces
    // from above, leave more.
    const auto cut = [&] {
      return internal::joined_pieces(neighbours, &kept) > pieces &&
             internal::joined_pieces(internal::k_nearest_all(
                 kept_points(), internal::kJoiningNeighbours)) > pieces;
    };
    if (cut()) {
      rejoin_pieces(neighbours, support, kept);
      if (cut()) return all;
    }
  }
  std::vector<int> supported;
  for (std::size_t i = 0; i < smoothed.size(); ++i)
    if (kept[i]) supported.push_back(static_cast<int>(i));
  return supported;
}

void restore_smoothing_bias(std::vector<Vec3>& smoothed, const std::vector<Vec3>& normals,
                            const std::vector<Vec3>& raw, double support) {
  const double radius = kBiasRadiusInSupports * support;
  if (smoothed.empty() || !(radius > 0.0)) return;
  Vec3 centroid;
  const auto cloud = centred_cloud(smoothed, centroid);
  // The bias varies over the smoothing's support, not from point to point: it is measured around
  // an even subset of the points, and each point takes a blend of the figures of its nearest.
  const std::size_t stride = std::max<std::size_t>(1, smoothed.size() / kBiasReferencePoints);
  auto reference = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  std::vector<Vec3> residuals;
  for (std::size_t i = 0; i < smoothed.size(); i += stride) {
    reference->push_back((*cloud)[i]);
    residuals.push_back(raw[i] - smoothed[i]);
  }
  FlannSearch search(true);
  search.setInputCloud(reference);
  const int least_neighbours = static_cast<int>(std::min(kBiasNeighbours, reference->size()));
  std::vector<Vec3> mean_residual(reference->size(), Vec3::Zero());
  const auto references = static_cast<std::ptrdiff_t>(reference->size());
#pragma omp parallel
  {
    pcl::Indices around;
    std::vector<float> squared;
#pragma omp for schedule(static)
    for (std::ptrdiff_t r = 0; r < references; ++r) {
      if (search.radiusSearch((*reference)[r], radius, around, squared) < least_neighbours)
        search.nearestKSearch((*reference)[r], least_neighbours, around, squared);
      for (int j : around) mean_residual[r] += residuals[j];
      mean_residual[r] /= static_cast<double>(around.size());
    }
  }
  const auto count = static_cast<std::ptrdiff_t>(smoothed.size());
  const int blend_count = static_cast<int>(std::min(kBiasBlended, reference->size()));
#pragma omp parallel
  {
    pcl::Indices nearest;
    std::vector<float> squared;
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      const Vec3& normal = normals[i];
      if (!normal.allFinite()) continue;
      search.nearestKSearch((*cloud)[i], blend_count, nearest, squared);
      // Inverse-distance weights: a change of the nearest reference makes no step, only a change
      // of the farthest of the few blended, where its weight is least.
      Vec3 bias = Vec3::Zero();
      double weight_sum = 0.0;
      for (std::size_t c = 0; c < nearest.size(); ++c) {
        const double weight = 1.0 / (std::sqrt(static_cast<double>(squared[c])) + 1e-12 * radius);
        bias += weight * mean_residual[nearest[c]];
        weight_sum += weight;
      }
      smoothed[i] += (bias / weight_sum).dot(normal) * normal;
    }
  }
}

double mls_deviation(const std::vector<Vec3>& points, double radius, int samples) {
  if (samples < 1) throw std::logic_error("mls_deviation: needs at least one sample");
  if (points.empty()) return 0.0;
  std::vector<int> measured;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / samples);
  for (std::size_t i = 0; i < points.size(); i += stride) measured.push_back(static_cast<int>(i));
  const MlsSurfaces surfaces(points, radius, &measured);
  std::vector<double> distances(measured.size(), 0.0);  // a point without a fit stays: 0
  for (std::size_t k = 0; k < measured.size(); ++k) {
    Vec3 projected, normal;
    if (surfaces.project(points[measured[k]], projected, normal))
      distances[k] = (points[measured[k]] - projected).norm();
  }
  return median(std::move(distances)) / kHalfNormalMedian;
}

double smooth_mesh(std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& faces,
                   int steps) {
  const std::vector<Vec3> noisy = points;
  const int count = static_cast<int>(points.size());
  // Each vertex's edge neighbours, once each (CSR).
  std::vector<std::pair<int, int>> edges;
  edges.reserve(6 * faces.size());
  for (const auto& face : faces)
    for (int c = 0; c < 3; ++c) {
      edges.emplace_back(face[c], face[(c + 1) % 3]);
      edges.emplace_back(face[(c + 1) % 3], face[c]);
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<int> offsets(count + 1, 0);
  for (const auto& edge : edges) ++offsets[edge.first + 1];
  for (int v = 0; v < count; ++v) offsets[v + 1] += offsets[v];

  constexpr double kLambda = 0.5, kMu = -0.53;
  std::vector<Vec3> moved(points.size());
  const auto pass = [&](double weight) {
#pragma omp parallel for schedule(static)
    for (int v = 0; v < count; ++v) {
      const int first = offsets[v], last = offsets[v + 1];
      if (first == last) {
        moved[v] = points[v];
        continue;
      }
      Vec3 mean = Vec3::Zero();
      for (int e = first; e < last; ++e) mean += points[edges[e].second];
      mean /= static_cast<double>(last - first);
      moved[v] = points[v] + weight * (mean - points[v]);
    }
    points.swap(moved);
  };
  for (int step = 0; step < steps; ++step) {
    pass(kLambda);
    pass(kMu);
  }
  // How far the vertices moved across the smoothed surface (area-weighted vertex normals).
  std::vector<Vec3> normals(points.size(), Vec3::Zero());
  for (const auto& face : faces) {
    const Vec3 area = (points[face[1]] - points[face[0]]).cross(points[face[2]] - points[face[0]]);
    for (int v : face) normals[v] += area;
  }
  double squares = 0.0;
  int moved_count = 0;
  for (int v = 0; v < count; ++v) {
    const double length = normals[v].norm();
    if (!(length > 0.0)) continue;
    squares += std::pow((noisy[v] - points[v]).dot(normals[v]) / length, 2);
    ++moved_count;
  }
  return moved_count > 0 ? std::sqrt(squares / moved_count) : 0.0;
}

}  // namespace vmas
