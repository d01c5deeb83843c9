#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "eval/envelope.hpp"
#include "eval/shape_distance.hpp"
#include "core/subsample.hpp"
#include "vmas/error.hpp"
#include "vmas/eval.hpp"

namespace vmas {

namespace internal {

// What the last measured reconstruction left to reuse: distances and visibility depend only on
// the primitives involved, which are recognised by their keys (Envelope::piece_key, solid_key).
struct SurfaceSideCache {                    // surface -> medial
  std::vector<double> distance;              // of every surface sample (see `exact`)
  std::vector<std::uint64_t> nearest;        // the key of the piece at that distance
  std::vector<char> exact;  // whether `distance` is the least; if not, it bounds it from above
  std::unordered_set<std::uint64_t> pieces;  // keys of every piece then
};

constexpr std::uint64_t kUnknown = 0;  // a sample's hider not yet looked for
constexpr std::uint64_t kNone = std::numeric_limits<std::uint64_t>::max();  // a visible sample

struct PieceSamples {  // medial -> surface: the uniform samples of one boundary piece
  std::vector<Vec3> points;
  std::vector<std::uint64_t> hider;  // key of a solid the sample is hidden in; kNone, kUnknown
  std::vector<double> distance;      // to the input; NaN until needed; -d: at most d, not exact
};

// EvalOptions::point_weights on the medial -> surface side: a boundary sample's distance counts
// by the weight of the input point nearest to it.
class PointWeights {
 public:
  PointWeights(const std::vector<Vec3>& points, std::vector<double> weights)
      : tree_(points), weights_(std::move(weights)) {}
  void apply(const std::vector<Vec3>& samples, std::vector<double>& distances) const {
    const auto count = static_cast<std::ptrdiff_t>(samples.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i)
      distances[i] *= weights_[tree_.nearest(samples[i])];
  }

 private:
  KdTree tree_;
  std::vector<double> weights_;
};

}  // namespace internal

using internal::BoundarySamples;
using internal::Bvh;
using internal::Envelope;
using internal::kInfinity;
using internal::kNone;
using internal::kUnknown;
using internal::PieceSamples;
using internal::PointWeights;
using internal::ShapeDistance;
using internal::SurfaceSideCache;

namespace {

// Hiders of the last samples that a sample is tried against before the tree of solids.
constexpr std::size_t kRecentHiders = 4;

// With maxima_only, a distance is searched exactly only from this share of the last maximum up
// (of the least of the largest boundary distances, which the maximum is refined around).
constexpr double kStopShare = 0.5;
// Without a last measurement, the maxima are estimated from every this many samples (the
// estimates are at most the maxima: the share of them is a threshold that is safe to use).
constexpr std::size_t kEstimateStride = 16;
// A `below` that asks each side for such an estimate.
constexpr double kEstimate = -1.0;

// Boundary samples of one measurement at most (a few hundred bytes each while measured).
constexpr double kMaxBoundarySamples = 5e5;

std::pair<double, double> max_and_mean(const std::vector<double>& values) {
  double max = 0.0, sum = 0.0;
  for (double v : values) {
    max = std::max(max, v);
    sum += v;
  }
  return {max, values.empty() ? 0.0 : sum / static_cast<double>(values.size())};
}

// The least of the `count` largest values (of all values when there are fewer); 0 for none.
double least_of_largest(std::vector<double> values, std::size_t count) {
  if (values.empty() || count == 0) return 0.0;
  count = std::min(count, values.size());
  std::nth_element(values.begin(), values.begin() + (count - 1), values.end(),
                   std::greater<double>());
  return values[count - 1];
}

// Below what a side's distances need not be exact: a share of the last measurement's figure
// (kEstimate without one); 0, every distance exact, unless only maxima are wanted.
double stop_threshold(const EvalOptions& options, double last) {
  if (!options.maxima_only) return 0.0;
  return last > 0.0 ? kStopShare * last : kEstimate;
}

// The largest distance of every kEstimateStride-th sample to the pieces of `envelope`, times
// the sample's weight (`weights`: one per sample, or empty).
double sparse_maximum(const Envelope& envelope, const std::vector<Vec3>& samples,
                      const std::vector<double>& weights) {
  const auto strides = static_cast<std::ptrdiff_t>(samples.size() / kEstimateStride);
  double largest = 0.0;
#pragma omp parallel for schedule(static) reduction(max : largest)
  for (std::ptrdiff_t k = 0; k < strides; ++k) {
    const auto i = static_cast<std::size_t>(k) * kEstimateStride;
    const double distance = envelope.boundary_distance(samples[i]);
    largest = std::max(largest, weights.empty() ? distance : distance * weights[i]);
  }
  return largest;
}

// The point with the largest value (the first of equals); the origin when there is none.
Vec3 worst_point(const std::vector<Vec3>& points, const std::vector<double>& values) {
  if (values.empty()) return Vec3::Zero();
  return points[std::max_element(values.begin(), values.end()) - values.begin()];
}

// The primitives of `envelope` not among `known` keys, with a tree over their boxes.
struct FreshPrimitives {
  std::vector<int> ids;
  std::vector<Box> boxes;
  std::optional<Bvh> tree;  // refers to boxes
};

template <class KeyOf, class BoxOf>
void find_fresh(int count, const std::unordered_set<std::uint64_t>& known, KeyOf key_of,
                BoxOf box_of, FreshPrimitives& fresh) {
  for (int id = 0; id < count; ++id) {
    if (known.count(key_of(id))) continue;
    fresh.ids.push_back(id);
    fresh.boxes.push_back(box_of(id));
  }
  fresh.tree.emplace(fresh.boxes);
}

// A solid that hides each sample of `flat` (into by_piece): looked for anew when the sample's
// hider is unknown or gone; a visible sample can only be hidden by a fresh solid.
void find_hiders(const Envelope& envelope, const FreshPrimitives& fresh_solids,
                 const std::unordered_set<std::uint64_t>& solids_now,
                 const std::vector<std::pair<PieceSamples*, int>>& by_piece,
                 const std::vector<std::pair<int, int>>& flat, double tolerance) {
  const auto flat_count = static_cast<std::ptrdiff_t>(flat.size());
#pragma omp parallel
  {
    // Neighbouring samples of a piece are mostly hidden by the same few solids: the last ones
    // found are tried first. Which hider a sample records does not matter: only whether it has
    // one while that solid is there.
    std::array<int, kRecentHiders> recent;
    recent.fill(-1);
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t f = 0; f < flat_count; ++f) {
      PieceSamples& entry = *by_piece[flat[f].first].first;
      const int piece = by_piece[flat[f].first].second, j = flat[f].second;
      const Vec3& p = entry.points[j];
      std::uint64_t& hider = entry.hider[j];
      if (hider != kUnknown && hider != kNone && solids_now.count(hider)) continue;
      if (hider == kNone) {
        const int owner = envelope.owner_solid(piece);
        fresh_solids.tree->any_containing(p, [&](int k) {
          const int id = fresh_solids.ids[k];
          if (id == owner || !envelope.deep_inside(id, p, tolerance)) return false;
          hider = envelope.solid_key(id);
          return true;
        });
        continue;
      }
      const int owner = envelope.owner_solid(piece);
      int id = -1;
      for (int solid : recent)
        if (solid >= 0 && solid != owner && envelope.deep_inside(solid, p, tolerance)) {
          id = solid;
          break;
        }
      if (id < 0) {
        id = envelope.hider(p, piece, tolerance);
        if (id >= 0) {
          std::copy_backward(recent.begin(), recent.end() - 1, recent.end());
          recent[0] = id;
        }
      }
      hider = id < 0 ? kNone : envelope.solid_key(id);
    }
  }
}

}  // namespace

void EvalOptions::validate() const {
  if (surface_samples < -1) {
    throw InvalidOption("surface_samples", "must be -1 (as many as vertices) or >= 0");
  }
  if (!(boundary_spacing >= 1e-4 && boundary_spacing <= 0.1)) {
    throw InvalidOption("boundary_spacing", "must be in [1e-4, 0.1] (fraction of the diagonal)");
  }
  if (refined_samples < 1 || refined_samples > 100000) {
    throw InvalidOption("refined_samples", "must be in [1, 100000]");
  }
  if (!(inside_tolerance >= 0.0 && inside_tolerance <= 0.01)) {
    throw InvalidOption("inside_tolerance", "must be in [0, 0.01] (fraction of the diagonal)");
  }
  for (const Vec3& p : lid_points)
    if (!p.allFinite()) throw InvalidOption("lid_points", "must be finite");
  for (double w : point_weights)
    if (!(w >= 0.0 && w <= 1.0)) throw InvalidOption("point_weights", "must be in [0, 1]");
  if (!point_weights.empty() && surface_samples != 0)
    throw InvalidOption("point_weights", "needs surface_samples 0 (random samples have no weight)");
  if (max_input_points > 0 && !maxima_only) {
    throw InvalidOption("max_input_points", "needs maxima_only (vertex_error has every point)");
  }
}

// What the Evaluator keeps between calls (a nested class of a public one: its members are
// exported with it, unlike the internal stages it holds).
struct Evaluator::Impl {
  Impl(const SurfaceInput& shape, const EvalOptions& options)
      : options(options), shape(shape), distance(shape, options.cloud_as_discs, options.lid_points) {}

  // Surface -> medial distance of every sample: exact where it is `below` or more, and under
  // `below` elsewhere (an upper bound of it, which is all the maximum needs when it is `below` or
  // more). kEstimate: `below` is a share of the largest distance of a few samples.
  const std::vector<double>& surface_side(const Envelope& envelope, double below);
  // Medial -> surface at the visible uniform samples `spacing` apart: their points and pieces,
  // and their distances to the input: exact where `below` or more, and under `below` elsewhere
  // (an upper bound of it). kEstimate: `below` is a share of the least of the refined_samples
  // largest distances of a few samples.
  void boundary_side(const Envelope& envelope, double spacing, double tolerance, double below,
                     BoundarySamples& boundary, std::vector<double>& to_surface);

  EvalOptions options;
  const SurfaceInput& shape;
  double diagonal = 0.0;
  std::vector<Vec3> samples;  // surface -> medial: the input points, then random ones
  std::vector<int> visit;     // the samples' indices in an order that keeps neighbours together
  std::vector<double> weights;  // of the samples' distances (EvalOptions::point_weights; empty: 1)
  std::optional<PointWeights> boundary_weights;  // medial -> surface, with weights
  ShapeDistance distance;     // medial -> surface
  // What the last measurement left to re-use, and what keep_memory() set aside.
  struct Memory {
    SurfaceSideCache surface;
    std::unordered_map<std::uint64_t, PieceSamples> boundary;  // by piece key
    double boundary_spacing = 0.0;             // of those samples
    std::unordered_set<std::uint64_t> solids;  // keys of every solid of the reconstruction
  };
  Memory memory, kept;
  // Of the last measurement: the surface side's maximum, the least of the boundary distances
  // that were refined.
  double last_surface_max = 0.0, last_refined_least = 0.0;
};

namespace {

// Validates before the Impl builds anything from the shape.
const SurfaceInput& checked(const SurfaceInput& shape, const EvalOptions& options) {
  options.validate();
  internal::check_shape(shape);
  if (!options.point_weights.empty() && options.point_weights.size() != shape.points.size())
    throw InvalidOption("point_weights", "must be empty or one per point of the shape (" +
                                             std::to_string(shape.points.size()) + ", got " +
                                             std::to_string(options.point_weights.size()) + ")");
  return shape;
}

}  // namespace

Evaluator::Evaluator(const SurfaceInput& shape, const EvalOptions& options)
    : impl_(std::make_unique<Impl>(checked(shape, options), options)) {
  Box bounds;
  for (const Vec3& p : shape.points) bounds.extend(p);
  impl_->diagonal = bounds.diagonal().norm();
  if (!std::isfinite(impl_->diagonal) || !(impl_->diagonal > 0.0)) {
    throw InvalidInput("shape has a non-finite coordinate or no extent");
  }
  const int random_count =
      options.surface_samples < 0 ? static_cast<int>(shape.points.size()) : options.surface_samples;
  impl_->samples = internal::surface_samples(shape, random_count, options.seed);
  const std::size_t points = shape.points.size();
  if (options.max_input_points > 0 && points > options.max_input_points) {
    const Subsample thin = subsample(shape.points, options.max_input_points);
    std::vector<Vec3> samples;
    samples.reserve(thin.kept.size() + impl_->samples.size() - points);
    for (int i : thin.kept) samples.push_back(shape.points[i]);
    samples.insert(samples.end(), impl_->samples.begin() + points, impl_->samples.end());
    impl_->samples = std::move(samples);
    if (!options.point_weights.empty())
      for (int i : thin.kept) impl_->weights.push_back(options.point_weights[i]);
  } else {
    impl_->weights = options.point_weights;
  }
  if (!options.point_weights.empty())
    impl_->boundary_weights.emplace(shape.points, impl_->options.point_weights);
  impl_->visit = internal::z_order(impl_->samples);
}

Evaluator::~Evaluator() = default;

// The boundary samples are kept without their points (most of their memory), which the next
// measurement samples again where it needs them.
void Evaluator::keep_memory() {
  Impl::Memory& kept = impl_->kept;
  kept.surface = impl_->memory.surface;
  kept.solids = impl_->memory.solids;
  kept.boundary_spacing = impl_->memory.boundary_spacing;
  kept.boundary.clear();
  for (const auto& [key, piece] : impl_->memory.boundary) {
    PieceSamples& copy = kept.boundary[key];
    copy.hider = piece.hider;
    copy.distance = piece.distance;
  }
}

void Evaluator::restore_memory() { impl_->memory = impl_->kept; }

std::vector<double> Evaluator::distances_to_shape(const std::vector<Vec3>& queries) const {
  return impl_->distance(queries);
}

EvalResult evaluate(const SurfaceInput& shape, const MedialMesh& medial,
                    const EvalOptions& options) {
  return Evaluator(shape, options)(medial);
}

// A sample whose nearest piece is still there is at most as far as before, and only the new
// pieces can be nearer.
const std::vector<double>& Evaluator::Impl::surface_side(const Envelope& envelope,
                                                          double below) {
  if (below == kEstimate) below = kStopShare * sparse_maximum(envelope, samples, weights);
  const bool reuse = !memory.surface.distance.empty();
  FreshPrimitives fresh_pieces;
  if (reuse)
    find_fresh(
        envelope.piece_count(), memory.surface.pieces,
        [&](int id) { return envelope.piece_key(id); },
        [&](int id) { return envelope.piece_box(id); }, fresh_pieces);
  std::unordered_set<std::uint64_t> pieces_now;
  for (int id = 0; id < envelope.piece_count(); ++id) pieces_now.insert(envelope.piece_key(id));
  SurfaceSideCache& cache = memory.surface;
  cache.distance.resize(samples.size());
  cache.nearest.resize(samples.size());
  cache.exact.resize(samples.size());
  // The nearest piece, or one nearer than `stop_below`; `piece`: the last one found by this
  // thread (samples next to each other are mostly near the same piece).
  const auto search = [&](std::ptrdiff_t i, double stop_below, int& piece) {
    cache.distance[i] = envelope.nearest_piece(samples[i], piece, stop_below);
    cache.nearest[i] = envelope.piece_key(piece);
    cache.exact[i] = !(cache.distance[i] < stop_below);
  };
  const auto sample_count = static_cast<std::ptrdiff_t>(samples.size());
#pragma omp parallel
  {
    int piece = -1;
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t k = 0; k < sample_count; ++k) {
      const int i = visit[k];
      if (!(reuse && pieces_now.count(cache.nearest[i]))) {
        search(i, below, piece);
        continue;
      }
      const Vec3& p = samples[i];
      double& d = cache.distance[i];
      int item = -1;
      const double fresh = fresh_pieces.tree->nearest(
          p, [&](int fresh_id) { return envelope.piece_distance(fresh_pieces.ids[fresh_id], p); },
          below, &item);
      if (fresh < d) {
        d = fresh;
        cache.nearest[i] = envelope.piece_key(fresh_pieces.ids[item]);
      }
      // Below `below` a bound will do; above it only an exact distance (the fresh pieces were all
      // searched: none stopped the search early).
      if (d < below) {
        cache.exact[i] = false;
      } else if (!cache.exact[i]) {
        search(i, below, piece);
      }
    }
  }
  cache.pieces = std::move(pieces_now);
  return cache.distance;
}

// The uniform samples of a piece that was already there keep their distance, and their hider
// while it is there.
void Evaluator::Impl::boundary_side(const Envelope& envelope, double spacing, double tolerance,
                                    double below, BoundarySamples& boundary,
                                    std::vector<double>& to_surface) {
  // Samples of another spacing (outsized primitives are sampled more coarsely) are not these.
  if (memory.boundary_spacing != spacing) memory.boundary.clear();
  memory.boundary_spacing = spacing;
  FreshPrimitives fresh_solids;
  find_fresh(
      envelope.solid_count(), memory.solids, [&](int id) { return envelope.solid_key(id); },
      [&](int id) { return envelope.solid_box(id); }, fresh_solids);
  std::unordered_set<std::uint64_t> solids_now;
  for (int id = 0; id < envelope.solid_count(); ++id) solids_now.insert(envelope.solid_key(id));
  std::unordered_map<std::uint64_t, PieceSamples> pieces;
  std::vector<std::pair<PieceSamples*, int>> by_piece;  // in piece order
  std::vector<std::pair<int, int>> flat;                // (index into by_piece, sample) to look at
  for (int piece = 0; piece < envelope.piece_count(); ++piece) {
    const std::uint64_t key = envelope.piece_key(piece);
    const auto [entry, first] = pieces.try_emplace(key);
    by_piece.emplace_back(&entry->second, piece);
    // Two coincident spheres give identical pieces: their samples are looked at once (a sample
    // on one is not inside the other).
    if (!first) continue;
    PieceSamples& samples_of_piece = entry->second;
    const auto known = memory.boundary.find(key);
    if (known != memory.boundary.end()) samples_of_piece = std::move(known->second);
    // Kept aside without its points (keep_memory): the same piece, sampled again, gives them.
    if (known == memory.boundary.end() ||
        samples_of_piece.points.size() != samples_of_piece.hider.size()) {
      BoundarySamples sampled;
      envelope.sample_piece(piece, spacing, sampled);
      samples_of_piece.points = std::move(sampled.points);
      if (known == memory.boundary.end()) {
        samples_of_piece.hider.assign(samples_of_piece.points.size(), kUnknown);
        samples_of_piece.distance.assign(samples_of_piece.points.size(),
                                         std::numeric_limits<double>::quiet_NaN());
      }
    }
    for (int j = 0; j < static_cast<int>(samples_of_piece.points.size()); ++j)
      flat.emplace_back(static_cast<int>(by_piece.size()) - 1, j);
  }
  find_hiders(envelope, fresh_solids, solids_now, by_piece, flat, tolerance);
  std::vector<double*> distances;
  for (const auto& [entry, piece] : by_piece)
    for (std::size_t j = 0; j < entry->points.size(); ++j) {
      if (entry->hider[j] != kNone) continue;
      boundary.points.push_back(entry->points[j]);
      boundary.pieces.push_back(piece);
      distances.push_back(&entry->distance[j]);
    }
  // Visible samples without a distance yet, or with a bound that no longer does, each once.
  std::vector<Vec3> unmeasured;
  std::vector<double*> slots;
  for (auto& [key, entry] : pieces)
    for (std::size_t j = 0; j < entry.points.size(); ++j) {
      const double known = entry.distance[j];
      if (entry.hider[j] != kNone || known >= 0.0 || -known < below) continue;
      unmeasured.push_back(entry.points[j]);
      slots.push_back(&entry.distance[j]);
    }
  if (below == kEstimate) {
    std::vector<Vec3> some;
    for (std::size_t k = 0; k < unmeasured.size(); k += kEstimateStride)
      some.push_back(unmeasured[k]);
    std::vector<double> estimates = distance(some);
    if (boundary_weights) boundary_weights->apply(some, estimates);
    const auto refined = static_cast<std::size_t>(options.refined_samples);
    below = kStopShare * least_of_largest(std::move(estimates), refined);
  }
  const std::vector<double> measured = distance(unmeasured, below);
  for (std::size_t k = 0; k < slots.size(); ++k)
    *slots[k] = measured[k] < below ? -measured[k] : measured[k];
  to_surface.resize(distances.size());
  for (std::size_t i = 0; i < distances.size(); ++i) to_surface[i] = std::abs(*distances[i]);
  memory.boundary = std::move(pieces);
  memory.solids = std::move(solids_now);
}

namespace {

// The distance to the input is 1-Lipschitz, so the maximum can only exceed a sample's value by
// the spacing: refined (twice, 4x finer) around the samples with the largest distances that
// could still hold it. The uniform samples and their distances go to `result` first.
void refine_medial_to_surface_max(const Envelope& envelope, const ShapeDistance& distance,
                                  const std::optional<PointWeights>& weights,
                                  const EvalOptions& options, double spacing, double tolerance,
                                  BoundarySamples boundary, std::vector<double> to_surface,
                                  EvalResult& result) {
  for (int round = 0; round < 2; ++round) {
    std::vector<std::size_t> order(boundary.points.size());
    std::iota(order.begin(), order.end(), 0);
    const std::size_t refined =
        std::min(order.size(), static_cast<std::size_t>(options.refined_samples));
    std::partial_sort(
        order.begin(), order.begin() + refined, order.end(), [&](std::size_t i, std::size_t j) {
          return to_surface[i] > to_surface[j] || (to_surface[i] == to_surface[j] && i < j);
        });
    BoundarySamples finer;
    for (std::size_t k = 0; k < refined; ++k) {
      const std::size_t i = order[k];
      if (to_surface[i] + spacing < result.medial_to_surface_max) break;
      envelope.sample_around(boundary.points[i], boundary.pieces[i], spacing, spacing / 4, finer);
    }
    spacing /= 4;
    if (round == 0) {  // done with the uniform samples: they go to the caller
      result.boundary_samples = std::move(boundary.points);
      result.boundary_error = std::move(to_surface);
    }
    boundary = envelope.visible(finer, tolerance);
    to_surface = distance(
        boundary.points, options.maxima_only ? result.medial_to_surface_max - spacing : -kInfinity);
    if (weights) weights->apply(boundary.points, to_surface);
    for (std::size_t i = 0; i < to_surface.size(); ++i) {
      if (to_surface[i] <= result.medial_to_surface_max) continue;
      result.medial_to_surface_max = to_surface[i];
      result.medial_to_surface_worst = boundary.points[i];
    }
  }
}

}  // namespace

EvalResult Evaluator::operator()(const MedialMesh& medial) {
  const EvalOptions& options = impl_->options;
  const Envelope envelope(medial);
  EvalResult result;
  result.diagonal = impl_->diagonal;
  // Only the maximum is wanted: samples stop at the first piece nearer than a share of the last
  // maximum, and are measured again exactly in the rare case that the maximum is below that (an
  // estimate is at most the maximum).
  // With weights, each figure (the last maxima, the estimates) is of weighted distances, and a
  // weight is at most 1: a distance below the threshold stays below it weighted.
  const double below = stop_threshold(options, impl_->last_surface_max);
  std::vector<double> weighted;
  const auto surface_side = [&](double stop_below) -> const std::vector<double>& {
    const std::vector<double>& distances = impl_->surface_side(envelope, stop_below);
    if (impl_->weights.empty()) return distances;
    weighted.resize(distances.size());
    for (std::size_t i = 0; i < distances.size(); ++i)
      weighted[i] = distances[i] * impl_->weights[i];
    return weighted;
  };
  const std::vector<double>* measured = &surface_side(below);
  if (below > 0.0 && max_and_mean(*measured).first < below) measured = &surface_side(0.0);
  const std::vector<double>& to_medial = *measured;

  // Medial -> surface: the uniform samples give the mean, the maximum is refined around them.
  const double tolerance = options.inside_tolerance * result.diagonal;
  double spacing = options.boundary_spacing * result.diagonal;
  // Work and memory bounded whatever the medial mesh: primitives far larger than the shape
  // are sampled more coarsely (the counts grow as 1 / spacing²).
  const double expected = envelope.sample_count(spacing);
  if (expected > kMaxBoundarySamples) spacing *= std::sqrt(expected / kMaxBoundarySamples);
  // Only the largest distances are refined (refined_samples of them): the others stop at a
  // share of the last measurement's smallest of those, and are measured again exactly in the
  // rare case that fewer are above it.
  const std::size_t refined = static_cast<std::size_t>(options.refined_samples);
  const double boundary_below = stop_threshold(options, impl_->last_refined_least);
  BoundarySamples boundary;
  std::vector<double> to_surface;
  // Weighted, a distance at or above the threshold was one before: it is exact.
  const auto boundary_side = [&](double stop_below) {
    boundary = {};
    impl_->boundary_side(envelope, spacing, tolerance, stop_below, boundary, to_surface);
    if (impl_->boundary_weights) impl_->boundary_weights->apply(boundary.points, to_surface);
  };
  boundary_side(boundary_below);
  if (boundary_below > 0.0 &&
      static_cast<std::size_t>(std::count_if(to_surface.begin(), to_surface.end(), [&](double d) {
        return d >= boundary_below;
      })) < std::min(refined, to_surface.size()))
    boundary_side(0.0);
  impl_->last_refined_least = least_of_largest(to_surface, refined);
  std::tie(result.medial_to_surface_max, result.medial_to_surface_mean) = max_and_mean(to_surface);
  result.medial_to_surface_worst = worst_point(boundary.points, to_surface);
  result.boundary_sample_count = boundary.points.size();
  refine_medial_to_surface_max(envelope, impl_->distance, impl_->boundary_weights, options,
                               spacing, tolerance, std::move(boundary), std::move(to_surface),
                               result);

  std::tie(result.surface_to_medial_max, result.surface_to_medial_mean) = max_and_mean(to_medial);
  result.surface_to_medial_worst = worst_point(impl_->samples, to_medial);
  impl_->last_surface_max = result.surface_to_medial_max;
  result.hausdorff = std::max(result.surface_to_medial_max, result.medial_to_surface_max);
  result.surface_sample_count = impl_->samples.size();
  if (options.maxima_only) {
    result.surface_to_medial_mean = result.medial_to_surface_mean = 0.0;
    result.boundary_samples.clear();
    result.boundary_error.clear();
    return result;
  }
  result.vertex_error.assign(to_medial.begin(), to_medial.begin() + impl_->shape.points.size());
  return result;
}

}  // namespace vmas
