#include "refine/refine.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "core/stopwatch.hpp"
#include "eval/envelope.hpp"
#include "optimise/connectivity.hpp"
#include "optimise/partition.hpp"
#include "optimise/projection.hpp"
#include "vmas/error.hpp"
#include "vmas/eval.hpp"
#include "vmas/vmas.hpp"

namespace vmas {

void RefineOptions::validate() const {
  if (max_moves < 0 || max_moves > 1000)
    throw InvalidOption("max_moves",
                        "must be between 0 and 1000 (got " + std::to_string(max_moves) + ")");
  if (!(min_gain >= 0.0 && min_gain < 1.0))
    throw InvalidOption("min_gain",
                        "must be in [0, 1) (got " + std::to_string(min_gain) + ")");
}

namespace {

// Spheres tried for removal per move, cheapest first.
constexpr std::size_t kRemovalCandidates = 10;
// A removal may leave its former vertices at most this fraction of the current error away from
// the reconstruction (before anything adapts to it).
constexpr double kRemovalMargin = 0.75;
// Spheres closer than this (a fraction of the diagonal, centres and radii) are one.
constexpr double kSameSphere = 1e-9;
// Steps before the final refits when a move alone did not help.
constexpr int kSettleSteps = 3;

// Unfrozen spheres other than `keep`, cheapest to remove first: the energy their vertices would
// gain by joining the best neighbouring sphere instead (weighted by their density: a dense region
// keeps its spheres).
std::vector<int> removal_order(const Skeletonizer& skeletonizer,
                               const std::vector<std::vector<int>>& adjacent, int keep) {
  const Shape& shape = skeletonizer.shape();
  const std::vector<Sphere>& spheres = skeletonizer.spheres();
  const std::vector<int>& labels = skeletonizer.labels();
  const double lambda = skeletonizer.options().lambda;
  const int count = static_cast<int>(spheres.size());
  std::vector<double> cost(count, 0.0);
  for (int v = 0; v < shape.size(); ++v) {
    const int own = labels[v];
    double best = std::numeric_limits<double>::infinity();
    for (int other : adjacent[own])
      best = std::min(best, vertex_energy(shape, v, spheres[other], lambda));
    cost[own] += (best - vertex_energy(shape, v, spheres[own], lambda)) * shape.error_weight(v);
  }
  std::vector<int> order;
  for (int c = 0; c < count; ++c)
    if (c != keep && !skeletonizer.frozen(c)) order.push_back(c);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return cost[a] < cost[b]; });
  return order;
}

// The interpolated sphere of the medial mesh (a sphere, or one along an edge or over a face) whose
// boundary passes closest to `p`, i.e. the one that puts a boundary point of the reconstruction
// there, and the spheres of its primitive (-1 for none).
struct Generator {
  Sphere sphere;
  std::array<int, 3> spheres{-1, -1, -1};
};

Generator generating_sphere(const MedialMesh& medial, const Vec3& p) {
  Generator best;
  double best_gap = std::numeric_limits<double>::infinity();
  const auto consider = [&](const Vec3& center, double radius, std::array<int, 3> spheres) {
    const double gap = (p - center).norm() - radius;
    if (gap < best_gap) {
      best_gap = gap;
      best = {{center, radius}, spheres};
    }
  };
  for (int i = 0; i < static_cast<int>(medial.spheres.size()); ++i)
    consider(medial.spheres[i].center, medial.spheres[i].radius, {i, -1, -1});
  constexpr int kSteps = 32;
  for (const auto& e : medial.edges) {
    const Sphere &a = medial.spheres[e[0]], &b = medial.spheres[e[1]];
    for (int i = 1; i < kSteps; ++i) {
      const double t = static_cast<double>(i) / kSteps;
      consider((1 - t) * a.center + t * b.center, (1 - t) * a.radius + t * b.radius,
               {e[0], e[1], -1});
    }
  }
  for (const auto& f : medial.faces) {
    const Sphere &a = medial.spheres[f[0]], &b = medial.spheres[f[1]], &c = medial.spheres[f[2]];
    for (int i = 1; i < kSteps; ++i)
      for (int j = 1; i + j < kSteps; ++j) {
        const double u = static_cast<double>(i) / kSteps, v = static_cast<double>(j) / kSteps;
        consider((1 - u - v) * a.center + u * b.center + v * c.center,
                 (1 - u - v) * a.radius + u * b.radius + v * c.radius, f);
      }
  }
  return best;
}

// Whether the larger one-sided error is surface -> medial (a part left uncovered) rather than
// medial -> surface (the reconstruction bulging out).
bool aims_at_uncovered(const EvalResult& now) {
  return now.surface_to_medial_max >= now.medial_to_surface_max;
}

// The cluster adjacency once `removed` is gone (`adjacent`: before), its vertices
// (`former_members`) having gone to their `labels` and every other cluster's id above it one
// lower: the pairs without it stay, and the graph's edges at its former vertices give the new
// ones (the graph is symmetric). The same lists as cluster_adjacency() of the new labels.
std::vector<std::vector<int>> adjacency_without(const Shape& shape,
                                                const std::vector<std::vector<int>>& adjacent,
                                                int removed, const std::vector<int>& labels,
                                                const std::vector<int>& former_members) {
  const auto renumbered = [removed](int c) { return c > removed ? c - 1 : c; };
  std::vector<std::vector<int>> adjacency(adjacent.size() - 1);
  for (int c = 0; c < static_cast<int>(adjacent.size()); ++c) {
    if (c == removed) continue;
    auto& list = adjacency[renumbered(c)];
    for (int other : adjacent[c])
      if (other != removed) list.push_back(renumbered(other));
  }
  for (int v : former_members)
    for (int i = shape.neighbour_offsets[v]; i < shape.neighbour_offsets[v + 1]; ++i) {
      const int a = labels[v], b = labels[shape.neighbours[i]];
      if (a == b) continue;
      adjacency[a].push_back(b);
      adjacency[b].push_back(a);
    }
  for (auto& list : adjacency) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return adjacency;
}

// Whether the vertices of sphere `removed` would all stay closer than `margin` to the
// reconstruction without it. Computed aside, without changing the skeletonizer: removing a sphere
// only relabels its own vertices (every other vertex keeps its nearest sphere), so they alone are
// partitioned again, exactly as remove_sphere() would (lowest id among equals). `adjacent`: the
// cluster adjacency as it is.
bool leaves_members_covered(const Skeletonizer& skeletonizer,
                            const std::vector<std::vector<int>>& adjacent, int removed,
                            double margin) {
  const Shape& shape = skeletonizer.shape();
  const double lambda = skeletonizer.options().lambda;
  std::vector<Sphere> spheres = skeletonizer.spheres();
  spheres.erase(spheres.begin() + removed);
  std::vector<int> labels = skeletonizer.labels();
  std::vector<int> former_members;
  for (int v = 0; v < shape.size(); ++v) {
    int& label = labels[v];
    if (label != removed) {
      if (label > removed) --label;
      continue;
    }
    former_members.push_back(v);
    double best = std::numeric_limits<double>::infinity();
    for (int c = 0; c < static_cast<int>(spheres.size()); ++c) {
      const double energy = vertex_energy(shape, v, spheres[c], lambda);
      if (energy < best) {
        best = energy;
        label = c;
      }
    }
  }
  const MedialMesh medial = build_medial_mesh(
      spheres, adjacency_without(shape, adjacent, removed, labels, former_members));
  std::vector<Vec3> members;
  for (int v : former_members) members.push_back(shape.points[v]);
  const std::vector<double> left = envelope_distances(medial, members);
  return left.empty() || *std::max_element(left.begin(), left.end()) < margin;
}

// Whether sphere `id` lies where another one is, up to rounding.
bool duplicates_a_sphere(const Skeletonizer& skeletonizer, int id) {
  const std::vector<Sphere>& spheres = skeletonizer.spheres();
  const double tolerance = kSameSphere * skeletonizer.shape().diagonal;
  for (int other = 0; other < static_cast<int>(spheres.size()); ++other)
    if (other != id && (spheres[other].center - spheres[id].center).norm() <= tolerance &&
        std::abs(spheres[other].radius - spheres[id].radius) <= tolerance)
      return true;
  return false;
}

// Adds a sphere where the reconstruction (`medial`, measured as `now`) is worst and removes the
// cheapest sphere whose removal leaves its vertices covered (energy is an average: the sphere of a
// thin part can be cheap while its removal opens a hole). The new sphere is frozen and comes last.
// Returns the removed sphere's id; -1 when the new sphere is one already there or no sphere can go
// (the new one is left in place: the caller restores its last state).
int add_and_remove(Skeletonizer& skeletonizer, const MedialMesh& medial, const EvalResult& now,
                   bool uncovered) {
  const MedialProjector& projector = skeletonizer.projector();
  // A surface point far from the reconstruction gets the medial ball touching it; a bulge of
  // the reconstruction gets the medial sphere under the interpolated sphere that makes it.
  Generator bulge;
  if (!uncovered) bulge = generating_sphere(medial, now.medial_to_surface_worst);
  const int added =
      uncovered ? skeletonizer.add_sphere_at(projector.nearest_vertex(now.surface_to_medial_worst))
                : skeletonizer.add_sphere(projector.project(bulge.sphere.center));
  // The ball there may be a sphere already (a bulge made by one sphere projects onto it): a copy
  // would only waste a sphere.
  if (duplicates_a_sphere(skeletonizer, added)) return -1;
  skeletonizer.freeze(added);
  // A bulge: its own spheres may go first (the new one takes their place).
  std::vector<int> order;
  for (int own : bulge.spheres)
    if (own >= 0 && !skeletonizer.frozen(own)) order.push_back(own);
  const auto adjacent = cluster_adjacency(skeletonizer.shape(), skeletonizer.labels(),
                                          static_cast<int>(skeletonizer.spheres().size()));
  for (int c : removal_order(skeletonizer, adjacent, added))
    if (std::find(order.begin(), order.end(), c) == order.end()) order.push_back(c);
  // A sphere never goes to where the density is lower than where it was.
  const std::vector<double>& density = skeletonizer.cluster_densities();
  if (!density.empty())
    order.erase(std::remove_if(order.begin(), order.end(),
                               [&](int c) { return density[c] > density[added]; }),
                order.end());
  for (std::size_t k = 0; k < order.size() && k < kRemovalCandidates; ++k) {
    if (!leaves_members_covered(skeletonizer, adjacent, order[k], kRemovalMargin * now.hausdorff))
      continue;
    skeletonizer.remove_sphere(order[k]);
    return order[k];
  }
  return -1;
}

// A move that did not help alone: the neighbours adapt to it (a few steps and the final refits;
// the new sphere is frozen).
void settle_around_move(Skeletonizer& skeletonizer) {
  for (int i = 0; i < kSettleSteps; ++i) skeletonizer.step();
  skeletonizer.final_refits();
}

// Whether a kept move lowered the side it aimed at by less than `min_gain` (a fraction): when
// both sides are close, the other one can hold the two-sided error while the aimed one drops.
bool gained_little(bool aimed_uncovered, const EvalResult& before, const EvalResult& after,
                   double min_gain) {
  const double aimed_before =
      aimed_uncovered ? before.surface_to_medial_max : before.medial_to_surface_max;
  const double aimed_after =
      aimed_uncovered ? after.surface_to_medial_max : after.medial_to_surface_max;
  return aimed_after > (1.0 - min_gain) * aimed_before;
}

}  // namespace

EvalOptions refinement_eval_options(bool smoothed) {
  // A measurement costs a few ms once the first is made (the Evaluator re-uses what it measured
  // of unchanged primitives).
  EvalOptions coarse;
  coarse.surface_samples = 0;
  coarse.boundary_spacing = 0.016;
  coarse.refined_samples = 8;
  coarse.maxima_only = true;
  coarse.cloud_as_discs = !smoothed;
  return coarse;
}

RefineReport refine_worst_served(Skeletonizer& skeletonizer, const SurfaceInput& surface,
                                 const RefineOptions& options, const ProgressCallback& progress) {
  options.validate();
  if (options.max_moves == 0) return {};
  const auto start = std::chrono::steady_clock::now();
  Evaluator evaluator(surface, refinement_eval_options());
  RefineReport report = refine_worst_served(skeletonizer, evaluator, options, progress);
  report.seconds = internal::seconds_since(start);
  return report;
}

FinishReport finish_skeleton(Skeletonizer& skeletonizer, Evaluator& evaluator,
                             const RefineOptions& options, bool refitted,
                             const ProgressCallback& progress) {
  options.validate();
  FinishReport finish;
  if (!refitted && !skeletonizer.final_refits(progress)) {
    finish.cancelled = true;
    return finish;
  }
  if (options.max_moves > 0) {
    finish.refine = refine_worst_served(skeletonizer, evaluator, options, progress);
    finish.cancelled = finish.refine.cancelled;
    finish.error = finish.refine.error_after;
  } else {
    finish.error = evaluator(skeletonizer.adjacency_mesh()).hausdorff;
  }
  return finish;
}

RefineReport refine_worst_served(Skeletonizer& skeletonizer, Evaluator& evaluator,
                                 const RefineOptions& options, const ProgressCallback& progress) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  RefineReport report;
  if (options.max_moves == 0) return report;
  // A measurement of the skeleton as it is; kept with its medial mesh and its components (a move
  // must not split the skeleton).
  MedialMesh medial;
  int components = 0;
  const auto measure = [&] {
    medial = skeletonizer.adjacency_mesh();
    components = component_count(medial);
    return evaluator(medial);
  };
  EvalResult best = measure();
  // A move that fails is undone: the next one is measured against the best state's primitives.
  evaluator.keep_memory();
  MedialMesh best_medial = medial;
  const int best_components = components;
  report.error_before = best.hausdorff;
  SkeletonizerState best_state = skeletonizer.state();
  // Spheres placed by kept moves stay frozen until the end, so that no later move undoes them.
  std::vector<bool> placed(skeletonizer.spheres().size(), false);
  int small_gains = 0;  // kept moves in a row that gained less than min_gain
  // A move aims at the worse side of the error; when that fails, once at the other side.
  bool aim_uncovered = aims_at_uncovered(best), aim_switched = false;
  const auto switch_aim = [&] {
    if (aim_switched) return false;
    aim_switched = true;
    aim_uncovered = !aim_uncovered;
    return true;
  };
  const auto report_progress = [&](double fraction) {
    return !progress ||
           progress(Progress{Progress::Phase::Refining, report.tried,
                             static_cast<int>(skeletonizer.spheres().size()),
                             skeletonizer.options().target.count(), best.hausdorff / best.diagonal,
                             report.tried + 1, options.max_moves, fraction});
  };
  while (report.tried < options.max_moves) {
    if (!report_progress(double(report.tried) / options.max_moves)) {
      report.cancelled = true;
      break;
    }
    const int removed = add_and_remove(skeletonizer, best_medial, best, aim_uncovered);
    if (removed < 0) {
      skeletonizer.restore(best_state);
      if (switch_aim()) continue;
      break;
    }
    ++report.tried;
    // First the move alone (the rest stays as it is); if that does not help, settled.
    // A move at the other side must gain noticeably: against smoothed noisy data a tiny gain
    // is as likely a loss against the true surface.
    const double needed = aim_switched ? (1.0 - options.min_gain) * best.hausdorff : best.hausdorff;
    const auto better = [&](const EvalResult& trial) {
      return trial.hausdorff < needed && components <= best_components;
    };
    EvalResult trial = measure();
    if (!better(trial)) {
      settle_around_move(skeletonizer);
      trial = measure();
    }
    if (!better(trial)) {
      skeletonizer.restore(best_state);
      evaluator.restore_memory();
      if (switch_aim()) continue;
      break;
    }
    placed.erase(placed.begin() + removed);
    placed.push_back(true);
    const bool small_gain = gained_little(aim_uncovered, best, trial, options.min_gain);
    best = std::move(trial);
    best_medial = medial;
    best_state = skeletonizer.state();
    evaluator.keep_memory();
    ++report.kept;
    small_gains = small_gain ? small_gains + 1 : 0;
    aim_uncovered = aims_at_uncovered(best);
    aim_switched = false;
    if (small_gains == 2) break;
  }
  for (int c = 0; c < static_cast<int>(placed.size()); ++c)
    if (placed[c]) skeletonizer.freeze(c, false);
  // Done: a cancellation now would cost the work, not save it.
  if (!report.cancelled) report_progress(1.0);
  report.error_after = best.hausdorff;
  report.seconds = internal::seconds_since(start);
  return report;
}

}  // namespace vmas
