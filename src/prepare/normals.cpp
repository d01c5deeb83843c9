#include "prepare/normals.hpp"


#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>

#include "core/cloud_graph.hpp"
#include "core/disjoint_sets.hpp"
#include "core/kdtree.hpp"
#include "core/principal_axes.hpp"
#include "core/sphere_lattice.hpp"
#include "pcl_backend/plane_fits.hpp"
#include "prepare/visibility.hpp"
#include "vmas/error.hpp"
#include "vmas/io.hpp"

namespace vmas {

using internal::centroid_of;
using internal::DisjointSets;
using internal::k_nearest_all;
using internal::Neighbourhoods;

namespace {

// Normalises every normal; a missing one (NaN from a degenerate neighbourhood, or zero length)
// becomes the direction away from the centroid so that it is finite and roughly outward before
// the orientation pass fixes its sign.
void sanitize(const std::vector<Vec3>& points, std::vector<Vec3>& normals) {
  const Vec3 centroid = centroid_of(points);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double length = normals[i].norm();
    if (std::isfinite(length) && length > 1e-12) {
      normals[i] /= length;
      continue;
    }
    const Vec3 away = points[i] - centroid;
    normals[i] = away.norm() > 1e-12 ? away.normalized() : Vec3::UnitZ();
  }
}

// Orientation agreement of the normals at two neighbouring points, in [-1, 1]: n_a compared with
// n_b mirrored across the bisecting plane of the edge (König & Gumhold 2009). On a smooth or
// sharp-edged surface the mirror maps one normal onto the other, so this is close to +1 (agree)
// or -1 (flip) even where the plain dot product n_a·n_b is near zero, such as box edges.
double agreement(const Vec3& n_a, const Vec3& n_b, const Vec3& edge_direction) {
  return n_a.dot(n_b) - 2.0 * n_a.dot(edge_direction) * n_b.dot(edge_direction);
}

// How much an edge runs along the normals at its ends, in [0, 1]: high between two close sheets
// (thin parts, doubled layers of misregistered scans), where the normals say nothing of the
// orientation across the gap.
double cross_sheet(const Vec3& n_a, const Vec3& n_b, const Vec3& edge_direction) {
  return 0.5 * (std::abs(n_a.dot(edge_direction)) + std::abs(n_b.dot(edge_direction)));
}

struct Edge {
  double weight;
  int a, b;  // a < b
};

// Weight of the MST edge: low when the propagation decision is clear-cut, high when it is
// ambiguous or crosses between sheets; the distance term breaks ties in favour of short edges.
double edge_weight(const Vec3& p_a, const Vec3& p_b, const Vec3& n_a, const Vec3& n_b,
                   double mean_spacing) {
  const Vec3 offset = p_b - p_a;
  const double length = offset.norm();
  const Vec3 direction = length > 0.0 ? Vec3(offset / length) : Vec3::Zero();
  return 1.0 - std::abs(agreement(n_a, n_b, direction)) + cross_sheet(n_a, n_b, direction) +
         1e-3 * length / mean_spacing;
}

// Minimum spanning forest (Kruskal) of the symmetric k-NN graph, as adjacency lists.
std::vector<std::vector<int>> spanning_forest(const std::vector<Vec3>& points,
                                              const std::vector<Vec3>& normals,
                                              const Neighbourhoods& neighbours) {
  const int count = static_cast<int>(points.size());
  const auto lists = [&](int i, int j) {
    const int* row = neighbours.row(i);
    return std::find(row, row + neighbours.width, j) != row + neighbours.width;
  };
  double spacing_sum = 0.0;
  std::size_t found = 0;
  std::vector<Edge> edges;
  edges.reserve(static_cast<std::size_t>(count) * neighbours.width);
  for (int i = 0; i < count; ++i) {
    for (int c = 0; c < neighbours.width; ++c) {
      const int j = neighbours.row(i)[c];
      if (j == i) continue;
      spacing_sum += (points[j] - points[i]).norm();
      ++found;
      // An edge found from both ends is kept once: from its lower end.
      if (i < j || !lists(j, i)) edges.push_back({0.0, std::min(i, j), std::max(i, j)});
    }
  }
  const double mean_spacing = std::max(spacing_sum / std::max<std::size_t>(found, 1), 1e-300);
  const auto edge_count = static_cast<std::ptrdiff_t>(edges.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < edge_count; ++k) {
    Edge& e = edges[k];
    e.weight = edge_weight(points[e.a], points[e.b], normals[e.a], normals[e.b], mean_spacing);
  }
  // A total order keeps the forest independent of the sort implementation (and of sorting the
  // two halves apart before merging them).
  const auto lighter = [](const Edge& x, const Edge& y) {
    return std::tie(x.weight, x.a, x.b) < std::tie(y.weight, y.a, y.b);
  };
  const auto middle = edges.begin() + edges.size() / 2;
#pragma omp parallel sections
  {
#pragma omp section
    std::sort(edges.begin(), middle, lighter);
#pragma omp section
    std::sort(middle, edges.end(), lighter);
  }
  std::inplace_merge(edges.begin(), middle, edges.end(), lighter);
  DisjointSets sets(count);
  std::vector<std::vector<int>> forest(count);
  for (const Edge& e : edges) {
    if (!sets.unite(e.a, e.b)) continue;
    forest[e.a].push_back(e.b);
    forest[e.b].push_back(e.a);
  }
  return forest;
}

// Directions spread evenly over the sphere.
std::vector<Vec3> sphere_directions(int count) {
  std::vector<Vec3> directions(count);
  for (int i = 0; i < count; ++i) directions[i] = internal::fibonacci_direction(i, count);
  return directions;
}

// True when a consistently oriented component points inward, by two votes in [-1, 1] added up.
// (1) The point of a closed surface that lies farthest along a direction d is on its convex
// hull, where the outward normal has n·d > 0, whatever the shape's concavities; many directions
// tolerate a few noisy extremes. (2) The divergence theorem: Σ (p − centroid)·n is three times
// the enclosed volume, positive for outward normals; it uses every point, so it still holds
// when the extremes are thin parts that noise smoothing folded onto one sheet, where (1) fails,
// and it is weak exactly where (1) is strong (thin plates enclose little volume).
bool points_inward(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                   const std::vector<int>& component, const std::vector<Vec3>& directions) {
  constexpr std::size_t kParallelFrom = 1000;  // points; smaller components stay on one thread
  const int direction_count = static_cast<int>(directions.size());
  std::vector<double> votes(direction_count);
#pragma omp parallel for schedule(static) if (component.size() >= kParallelFrom)
  for (int k = 0; k < direction_count; ++k) {
    const Vec3& d = directions[k];
    int extreme = component.front();
    for (int i : component)
      if (points[i].dot(d) > points[extreme].dot(d)) extreme = i;
    votes[k] = normals[extreme].dot(d);
  }
  double extremes = 0.0;
  for (double vote : votes) extremes += vote;  // in direction order, whatever the thread count
  return extremes / static_cast<double>(directions.size()) +
             outward_flux(points, normals, component) <
         0.0;
}

void orient(const std::vector<Vec3>& points, std::vector<Vec3>& normals,
            const Neighbourhoods& neighbours) {
  sanitize(points, normals);
  const int count = static_cast<int>(points.size());
  const auto forest = spanning_forest(points, normals, neighbours);
  const auto directions = sphere_directions(256);
  std::vector<char> visited(count, 0);
  std::vector<int> component;
  for (int root = 0; root < count; ++root) {
    if (visited[root]) continue;
    // Breadth-first over the tree: each normal takes its sign from its parent's.
    component.assign(1, root);
    visited[root] = 1;
    for (std::size_t head = 0; head < component.size(); ++head) {
      const int i = component[head];
      for (int j : forest[i]) {
        if (visited[j]) continue;
        visited[j] = 1;
        const Vec3 offset = points[j] - points[i];
        const double length = offset.norm();
        const Vec3 direction = length > 0.0 ? Vec3(offset / length) : Vec3::Zero();
        if (agreement(normals[i], normals[j], direction) < 0.0) normals[j] = -normals[j];
        component.push_back(j);
      }
    }
    if (points_inward(points, normals, component, directions))
      for (int i : component) normals[i] = -normals[i];
  }
}

// Median distance from a point to its nearest other point.
double median_spacing(const std::vector<Vec3>& points, const Neighbourhoods& neighbours) {
  std::vector<double> nearest;
  nearest.reserve(points.size());
  for (int i = 0; i < neighbours.size(); ++i)
    for (int c = 0; c < neighbours.width; ++c)
      if (const int j = neighbours.row(i)[c]; j != i) {
        nearest.push_back((points[j] - points[i]).norm());
        break;
      }
  if (nearest.empty()) return 0.0;
  const auto middle = nearest.begin() + nearest.size() / 2;
  std::nth_element(nearest.begin(), middle, nearest.end());
  return *middle;
}

// How the normals at the two ends of each k-NN edge agree, and how much the edge crosses between
// sheets (row-major, as the neighbourhoods; the score smoothing reads every edge at each step).
struct EdgeReading {
  double agreement = 0.0, cross_sheet = 1.0;
};

std::vector<EdgeReading> read_edges(const std::vector<Vec3>& points,
                                    const std::vector<Vec3>& normals,
                                    const Neighbourhoods& neighbours) {
  std::vector<EdgeReading> edges(neighbours.indices.size());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < neighbours.size(); ++i)
    for (int c = 0; c < neighbours.width; ++c) {
      const int j = neighbours.row(i)[c];
      if (j == i) continue;
      const Vec3 direction = (points[j] - points[i]).stableNormalized();
      EdgeReading& edge = edges[static_cast<std::size_t>(i) * neighbours.width + c];
      edge.agreement = agreement(normals[i], normals[j], direction);
      edge.cross_sheet = cross_sheet(normals[i], normals[j], direction);
    }
  return edges;
}

// One step of smoothing the visibility scores over the k-NN graph: each point keeps half its
// score and takes half its neighbours' mean, each carried over with the sign the two normals'
// agreement gives and weighted by how clear that agreement is (nothing across sheets).
std::vector<double> smooth_scores(const Neighbourhoods& neighbours,
                                  const std::vector<EdgeReading>& edges,
                                  const std::vector<double>& scores) {
  std::vector<double> smoothed(scores.size());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < neighbours.size(); ++i) {
    double sum = 0.0;
    int terms = 0;
    for (int c = 0; c < neighbours.width; ++c) {
      const int j = neighbours.row(i)[c];
      if (j == i) continue;
      const EdgeReading& edge = edges[static_cast<std::size_t>(i) * neighbours.width + c];
      const double clarity = std::max(std::abs(edge.agreement) - edge.cross_sheet, 0.0);
      sum += std::copysign(clarity, edge.agreement) * scores[j];
      ++terms;
    }
    smoothed[i] = 0.5 * scores[i] + (terms > 0 ? 0.5 * sum / terms : 0.0);
  }
  return smoothed;
}

}  // namespace

void orient_smoothed_normals(const std::vector<Vec3>& points, std::vector<Vec3>& normals, int k) {
  // Pixels of a few spacings hold several points of the front surface (no see-through gaps).
  constexpr double kPixelInSpacings = 2.5;
  // Steps of score smoothing: enough to settle isolated wrong votes.
  constexpr int kScoreSmoothingSteps = 3;
  // A region that the views turn over holds at least this share of the points: smaller ones are
  // the views' own mistakes (thin parts seen from both sides, cavities) as often as the tree's
  // (1 and 5 % gave the same benchmark figures within their spread).
  constexpr double kLeastRegionShare = 0.02;
  NormalOptions{k}.validate();
  if (normals.size() != points.size())
    throw InvalidInput("cannot orient " + std::to_string(normals.size()) + " normals for " +
                       std::to_string(points.size()) + " points");
  if (points.empty()) return;
  const Neighbourhoods neighbours = k_nearest_all(points, k);
  orient(points, normals, neighbours);
  const std::vector<EdgeReading> edges = read_edges(points, normals, neighbours);
  std::vector<double> scores = visibility_votes(
      points, normals, kPixelInSpacings * median_spacing(points, neighbours));
  for (int step = 0; step < kScoreSmoothingSteps; ++step)
    scores = smooth_scores(neighbours, edges, scores);
  // The regions where the views disagree with the tree, joined along clear edges.
  const int count = static_cast<int>(points.size());
  DisjointSets regions(count);
  for (int i = 0; i < count; ++i) {
    if (!(scores[i] < 0.0)) continue;
    for (int c = 0; c < neighbours.width; ++c) {
      const int j = neighbours.row(i)[c];
      if (j == i || !(scores[j] < 0.0)) continue;
      const EdgeReading& edge = edges[static_cast<std::size_t>(i) * neighbours.width + c];
      if (edge.agreement > 0.0 && edge.cross_sheet < 0.5) regions.unite(i, j);
    }
  }
  std::vector<int> region_size(count, 0);
  for (int i = 0; i < count; ++i)
    if (scores[i] < 0.0) ++region_size[regions.find(i)];
  for (int i = 0; i < count; ++i)
    if (scores[i] < 0.0 && region_size[regions.find(i)] >= kLeastRegionShare * count)
      normals[i] = -normals[i];
}

double sign_disagreement(const std::vector<Vec3>& points, const std::vector<Vec3>& normals) {
  constexpr int kNeighbours = 8;
  constexpr double kAcrossTangent = 0.3;  // |n·d| / |d| above this: another sheet
  constexpr int kProbes = 4000;           // points looked at, evenly through the cloud
  const int count = static_cast<int>(points.size());
  if (count <= kNeighbours || normals.size() != points.size()) return 0.0;
  const KdTree tree(points);
  const int stride = std::max(1, count / kProbes);
  std::size_t pairs = 0, opposite = 0;
#pragma omp parallel reduction(+ : pairs, opposite)
  {
    std::vector<int> row;
    std::vector<double> squared;
#pragma omp for schedule(static)
    for (int i = 0; i < count; i += stride) {
      tree.k_nearest(points[i], kNeighbours + 1, row, squared);
      for (int j : row) {
        if (j == i) continue;
        const Vec3 offset = points[j] - points[i];
        if (std::abs(normals[i].dot(offset)) > kAcrossTangent * offset.norm()) continue;
        ++pairs;
        opposite += normals[i].dot(normals[j]) < 0.0;
      }
    }
  }
  return pairs > 0 ? static_cast<double>(opposite) / static_cast<double>(pairs) : 0.0;
}

double outward_flux(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                    const std::vector<int>& subset) {
  const auto for_each_point = [&](const auto& visit) {
    if (subset.empty())
      for (std::size_t i = 0; i < points.size(); ++i) visit(i);
    else
      for (int i : subset) visit(static_cast<std::size_t>(i));
  };
  Vec3 centroid = Vec3::Zero();
  std::size_t count = 0;
  for_each_point([&](std::size_t i) {
    centroid += points[i];
    ++count;
  });
  if (count == 0) return 0.0;
  centroid /= static_cast<double>(count);
  double flux = 0.0, reach = 0.0;
  for_each_point([&](std::size_t i) {
    flux += (points[i] - centroid).dot(normals[i]);
    reach += (points[i] - centroid).norm();
  });
  return reach > 0.0 ? flux / reach : 0.0;
}

void NormalOptions::validate() const {
  if (k < 3 || k > 200)
    throw InvalidOption("k", "must be between 3 and 200 (got " + std::to_string(k) + ")");
}

namespace {

// Surface variation λ₀ / (λ₀ + λ₁ + λ₂) of a neighbourhood's covariance above which its plane fit
// is refit: 0 on a plane, at most 0.02 on the smooth test shapes (sphere, torus, capsule) at
// k = 16, up to 1/3 where the neighbours fill a volume, as they do where they straddle the two
// faces of a thin part or the two sides of an edge.
constexpr float kStraddlingVariation = 0.05f;

// The unit normal of the plane through points[i] that fits its neighbours `row` (`width` of them)
// by iteratively reweighted least squares, starting from `normal`: Cauchy weights of the
// distances to the current plane through the point, on the scale of twice their median. The
// neighbours on the point's own sheet are the nearer ones, so each pass weighs the other sheet
// less, and the fit settles on the point's own sheet instead of the tilted plane between the two
// that PCA fits. Deterministic; `normal` itself when the weighted covariance is degenerate.
Vec3 refit_on_own_sheet(const std::vector<Vec3>& points, const int* row, int width, int i,
                        Vec3 normal) {
  constexpr int kPasses = 3;
  constexpr double kScaleInMedians = 2.0;
  std::vector<double> distances(width), sorted(width), weights(width);
  for (int pass = 0; pass < kPasses; ++pass) {
    for (int c = 0; c < width; ++c)
      distances[c] = std::abs((points[row[c]] - points[i]).dot(normal));
    sorted = distances;
    std::nth_element(sorted.begin(), sorted.begin() + width / 2, sorted.end());
    const double scale = kScaleInMedians * sorted[width / 2];
    if (!(scale > 0.0)) break;  // most neighbours on the plane already
    Vec3 mean = Vec3::Zero();
    double weight_sum = 0.0;
    for (int c = 0; c < width; ++c) {
      weights[c] = 1.0 / (1.0 + std::pow(distances[c] / scale, 2));
      mean += weights[c] * (points[row[c]] - points[i]);
      weight_sum += weights[c];
    }
    mean /= weight_sum;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (int c = 0; c < width; ++c) {
      const Vec3 offset = points[row[c]] - points[i] - mean;
      covariance += weights[c] * offset * offset.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
    if (eigen.info() != Eigen::Success || !eigen.eigenvectors().col(0).allFinite()) break;
    normal = eigen.eigenvectors().col(0);
  }
  return normal;
}

// The unit normal of every point's neighbourhood: its least-squares plane, refit on the point's
// own sheet where the neighbourhood straddles two (refit_on_own_sheet); NaN where the
// neighbourhood is degenerate.
std::vector<Vec3> fitted_normals(const std::vector<Vec3>& points,
                                 const Neighbourhoods& neighbours) {
  const int count = static_cast<int>(points.size());
  const internal::PlaneFits planes(points);
  std::vector<Vec3> normals(count);
#pragma omp parallel
  {
    std::vector<int> indices(neighbours.width);
    float variation = 0.0f;
#pragma omp for schedule(static)
    for (int i = 0; i < count; ++i) {
      std::copy(neighbours.row(i), neighbours.row(i) + neighbours.width, indices.begin());
      normals[i] = planes.normal(indices, variation);
      if (variation > kStraddlingVariation && normals[i].allFinite())
        normals[i] = refit_on_own_sheet(points, neighbours.row(i), neighbours.width, i, normals[i]);
    }
  }
  return normals;
}

void check_enough_points(int count, int k, const char* what) {
  if (count < k + 1)
    throw InvalidInput("too few points (" + std::to_string(count) + ") to " + what +
                       " with k=" + std::to_string(k));
}

}  // namespace

std::vector<Vec3> estimate_normals(const std::vector<Vec3>& points, const NormalOptions& options) {
  options.validate();
  check_enough_points(static_cast<int>(points.size()), options.k, "estimate normals");
  return estimate_normals(points, options, k_nearest_all(points, options.k));
}

std::vector<Vec3> estimate_normals(const std::vector<Vec3>& points, const NormalOptions& options,
                                   const Neighbourhoods& neighbours) {
  options.validate();
  check_enough_points(static_cast<int>(points.size()), options.k, "estimate normals");
  std::vector<Vec3> normals = fitted_normals(points, neighbours);  // NaN where degenerate
  orient(points, normals, neighbours);
  return normals;
}

void fill_missing_normals(const std::vector<Vec3>& points, std::vector<Vec3>& normals, int k) {
  const NormalOptions options{k};
  options.validate();
  const auto missing = [&](std::size_t i) {
    return !normals[i].allFinite() || !(normals[i].squaredNorm() > 0.0);
  };
  std::vector<int> wanted;
  for (std::size_t i = 0; i < normals.size(); ++i)
    if (missing(i)) wanted.push_back(static_cast<int>(i));
  if (wanted.empty()) return;
  check_enough_points(static_cast<int>(points.size()), options.k, "estimate normals");
  const KdTree tree(points);
  const Vec3 centroid = centroid_of(points);
  std::vector<Vec3> filled(wanted.size());
#pragma omp parallel
  {
    std::vector<int> row;
    std::vector<double> squared;
#pragma omp for schedule(static)
    for (std::ptrdiff_t w = 0; w < static_cast<std::ptrdiff_t>(wanted.size()); ++w) {
      const int i = wanted[w];
      tree.k_nearest(points[i], options.k + 1, row, squared);
      const internal::PrincipalAxes fit = internal::principal_axes(points, row);
      Vec3 normal = fit.normal();
      if (!fit.valid || !normal.allFinite()) normal = points[i] - centroid;
      // The sign the neighbours' own normals agree on (away from the centroid if none has one).
      double vote = 0.0;
      for (int j : row)
        if (!missing(j)) vote += normal.dot(normals[j]);
      if (vote == 0.0) vote = normal.dot(points[i] - centroid);
      filled[w] = (vote < 0.0 ? -normal : normal).normalized();
      if (!filled[w].allFinite()) filled[w] = Vec3::UnitZ();
    }
  }
  for (std::size_t w = 0; w < wanted.size(); ++w) normals[wanted[w]] = filled[w];
}

void refit_given_normals(const std::vector<Vec3>& points, std::vector<Vec3>& normals, int k,
                         std::vector<Vec3> fitted) {
  // cos 60°: a fit further off the file's normal is not trusted to read the surface.
  constexpr double kLeastAgreement = 0.5;
  if (normals.size() != points.size() || (!fitted.empty() && fitted.size() != points.size()))
    throw InvalidInput("cannot refit " + std::to_string(normals.size()) + " normals for " +
                       std::to_string(points.size()) + " points");
  fill_missing_normals(points, normals, k);
  if (fitted.empty()) {
    if (static_cast<int>(points.size()) < k + 1) return;
    fitted = fitted_normals(points, k_nearest_all(points, k));
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!fitted[i].allFinite() || !(fitted[i].norm() > 0.0)) continue;
    const Vec3 fit = fitted[i].normalized();
    const double cosine = fit.dot(normals[i].stableNormalized());
    if (std::abs(cosine) >= kLeastAgreement) normals[i] = cosine < 0.0 ? Vec3(-fit) : fit;
  }
}

void orient_normals(const std::vector<Vec3>& points, std::vector<Vec3>& normals, int k) {
  NormalOptions{k}.validate();
  if (normals.size() != points.size())
    throw InvalidInput("cannot orient " + std::to_string(normals.size()) + " normals for " +
                       std::to_string(points.size()) + " points");
  if (points.empty()) return;
  orient(points, normals, k_nearest_all(points, k));
}

}  // namespace vmas
