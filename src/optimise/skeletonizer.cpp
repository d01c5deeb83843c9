#include "vmas/skeletonizer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "core/density_mean.hpp"
#include "core/stopwatch.hpp"
#include "core/validate_member.hpp"
#include "optimise/connectivity.hpp"
#include "optimise/partition.hpp"
#include "optimise/projection.hpp"
#include "optimise/shape.hpp"
#include "optimise/split.hpp"
#include "optimise/topology.hpp"
#include "optimise/update.hpp"
#include "vmas/error.hpp"
#include "vmas/vmas.hpp"

namespace vmas {

void SkeletonizerOptions::check_lambda(const std::string& option, double value) {
  if (!(value >= 0.0 && value <= kMaxLambda))
    throw InvalidOption(option, "must be in [0, 1e6] (got " + std::to_string(value) + ")");
}

void SkeletonizerOptions::validate() const {
  check_lambda("lambda", lambda);
  check_lambda("final_lambda", final_lambda);
  if (final_rounds < 0 || final_rounds > 100)
    throw InvalidOption("final_rounds",
                        "must be between 0 and 100 (got " + std::to_string(final_rounds) + ")");
  if (target.spheres < 0)
    throw InvalidOption("target.spheres",
                        "must be at least 1 (got " + std::to_string(target.spheres) + ")");
  if (!(target.error >= 0.0 && target.error < 1.0))
    throw InvalidOption("target.error", "must be in (0, 1), relative to the bounding-box diagonal (got " +
                                     std::to_string(target.error) + ")");
  if (target.spheres > 0 && target.error > 0.0)
    throw InvalidOption("target.error", "cannot go with spheres: give one or the other");
  if (max_spheres < 1) throw InvalidOption("max_spheres", "must be at least 1");
  if (target.count() > max_spheres)
    throw InvalidOption("target.spheres", "must be at most " + std::to_string(max_spheres) + " (got " +
                                       std::to_string(target.count()) + ")");
  if (max_iterations < 1) throw InvalidOption("max_iterations", "must be at least 1");
  if (!(convergence >= 0.0 && convergence < 1.0))
    throw InvalidOption("convergence",
                        "must be in [0, 1) (got " + std::to_string(convergence) + ")");
  if (split_interval < 1) throw InvalidOption("split_interval", "must be at least 1");
  if (settle_iterations < 0 || max_settle_iterations < settle_iterations)
    throw InvalidOption("settle_iterations", "must be in [0, max_settle_iterations]");
  if (min_cluster_size < 1) throw InvalidOption("min_cluster_size", "must be at least 1");
  internal::validate_member("update", update);
  internal::validate_member("shrinking_ball", shrinking_ball);
  internal::validate_member("split", split);
}

namespace {

using internal::Clock;
using internal::seconds_since;

// Re-seeding rounds for tiny clusters after each final re-partition.
constexpr int kFinalReseeds = 4;

// The coarse start (SkeletonizerOptions::coarse_start) runs on about max(1/kCoarseShare of the
// vertices, kCoarseVerticesPerSphere per sphere), when that is at most kCoarseAtMost of them.
constexpr std::size_t kCoarseShare = 4;
constexpr std::size_t kCoarseVerticesPerSphere = 50;
constexpr double kCoarseAtMost = 0.7;

// A sphere that its last fit and projection moved less than this (a fraction of the diagonal),
// with the same members since, is settled: fitting it again would move it by rounding only.
constexpr double kSettledMove = 1e-9;

}  // namespace

Skeletonizer::Skeletonizer(Shape shape, const SkeletonizerOptions& options)
    : shape_(std::move(shape)), options_(options), projector_(std::make_unique<MedialProjector>(shape_, options.shrinking_ball)) {
  options_.validate();
  check_target_fits(options_.target);
  // One cluster holding every vertex: fit its sphere from the centroid, then project it.
  std::vector<int> all(shape_.size());
  Vec3 centroid = Vec3::Zero();
  for (int v = 0; v < shape_.size(); ++v) {
    all[v] = v;
    centroid += shape_.points[v];
  }
  centroid /= shape_.size();
  double mean_distance = 0.0;
  for (const Vec3& p : shape_.points) mean_distance += (p - centroid).norm();
  Sphere sphere{centroid, mean_distance / shape_.size()};
  sphere = fit_sphere(shape_, all, sphere, options_.lambda, options_.update);
  if (options_.project) sphere = projector_->project(sphere.center);
  spheres_.push_back(sphere);
  frozen_.push_back(false);
  add_key();
  repartition();
}

Skeletonizer::~Skeletonizer() = default;

void Skeletonizer::repartition() {
  const auto start = Clock::now();
  partition(shape_, spheres_, options_.lambda, labels_, vertex_energies_, energies_current_,
            &partitioned_spheres_);
  partitioned_spheres_ = spheres_;
  energies_current_ = true;
  rebuild_members();
  times_.partition += seconds_since(start);
  refresh_errors(false);  // partition() left E_v of the assigned spheres in vertex_energies_
}

bool Skeletonizer::reseed_tiny_clusters(bool serving_balls_only) {
  const int count = static_cast<int>(spheres_.size());
  std::vector<int> tiny;
  std::vector<int> donors;  // clusters that may give up their worst vertex, worst error first
  for (int c = 0; c < count; ++c) {
    if (frozen_[c]) continue;
    if (static_cast<int>(members_[c].size()) < options_.min_cluster_size)
      tiny.push_back(c);
    else
      donors.push_back(c);
  }
  if (tiny.empty()) return false;
  std::stable_sort(donors.begin(), donors.end(),
                   [&](int a, int b) { return worst_errors_[a] > worst_errors_[b]; });
  // Each tiny sphere becomes the ball at the worst vertex of the next donor (with
  // serving_balls_only: the next whose ball serves that vertex better than its own sphere).
  bool moved = false;
  std::size_t next_donor = 0;
  for (int c : tiny) {
    while (next_donor < donors.size()) {
      const int worst = worst_vertex(donors[next_donor++]);
      const Sphere ball = projector_->ball_at(worst);
      if (serving_balls_only &&
          !(vertex_energy(shape_, worst, ball, options_.lambda) < vertex_energies_[worst]))
        continue;
      spheres_[c] = ball;
      moved = true;
      break;
    }
  }
  if (moved) energies_current_ = false;
  return moved;
}

int Skeletonizer::worst_vertex(int cluster) const {
  int worst = members_[cluster].front();
  for (int v : members_[cluster])
    if (vertex_energies_[v] * shape_.error_weight(v) >
        vertex_energies_[worst] * shape_.error_weight(worst))
      worst = v;
  return worst;
}

double Skeletonizer::split_error(int cluster) const {
  return cluster_densities_.empty()
             ? cluster_errors_[cluster]
             : cluster_errors_[cluster] * Shape::density_weight(cluster_densities_[cluster]);
}

void Skeletonizer::refresh_errors(bool spheres_moved) {
  refresh_errors(std::vector<char>(spheres_moved ? spheres_.size() : 0, 1));
}

void Skeletonizer::refresh_errors(const std::vector<char>& moved) {
  const int count = static_cast<int>(spheres_.size());
  const bool every_vertex = !energies_current_;
  const std::vector<double>& density = shape_.density;
  std::vector<double> cluster_energy(count, 0.0);
  cluster_errors_.assign(count, 0.0);
  worst_errors_.assign(count, 0.0);
  cluster_densities_.assign(density.empty() ? 0 : count, 1.0);
#pragma omp parallel
  {
    if (!moved.empty()) {
      // By vertex, not by cluster: a cluster's members are scattered over the vertex array, and
      // threads writing interleaved entries would keep taking each other's cache lines.
#pragma omp for schedule(static)
      for (int v = 0; v < shape_.size(); ++v)
        if (every_vertex || moved[labels_[v]])
          vertex_energies_[v] = vertex_energy(shape_, v, spheres_[labels_[v]], options_.lambda);
    }
#pragma omp for schedule(dynamic)
    for (int c = 0; c < count; ++c) {
      double energy = 0.0, area = 0.0, worst = 0.0;
      internal::DensityMean mean;
      for (int v : members_[c]) {
        energy += vertex_energies_[v];
        area += shape_.area[v];
        if (shape_.area[v] > 0.0)
          worst = std::max(worst, vertex_energies_[v] / shape_.area[v] * shape_.error_weight(v));
        if (!density.empty()) mean.add(density[v], shape_.area[v]);
      }
      cluster_energy[c] = energy;
      cluster_errors_[c] = area > 0.0 ? energy / area : 0.0;
      worst_errors_[c] = worst;
      if (!density.empty()) cluster_densities_[c] = mean.value();
    }
  }
  if (!moved.empty()) energies_current_ = true;
  total_error_ = 0.0;
  for (double energy : cluster_energy) total_error_ += energy;
  total_error_ /= shape_.total_area;
}

double Skeletonizer::step() {
  repartition();
  // A cluster that shrank to a handful of vertices carries no shape information: its sphere is
  // better spent where the error is largest (this keeps the sphere count exact).
  if (reseed_tiny_clusters()) repartition();
  refresh_errors(fit_and_project(options_.lambda));
  return total_error_;
}

std::vector<char> Skeletonizer::fit_and_project(double lambda) {
  const int count = static_cast<int>(spheres_.size());
  const auto start = Clock::now();
  std::vector<Sphere> fitted = spheres_;
  // Each sphere is fitted and projected by the same thread, in one parallel loop: a loop per
  // stage would add a barrier, and on a virtual machine waking the waiting threads costs ~0.1 ms.
  // The summary's update and projection times split the loop's wall time by their thread time.
  double fit_seconds = 0.0, projection_seconds = 0.0;
  if (pass_over_settled_) last_fits_.resize(count);
#pragma omp parallel for schedule(dynamic) reduction(+ : fit_seconds, projection_seconds)
  for (int c = 0; c < count; ++c) {
    if (frozen_[c] || (pass_over_settled_ && settled(c, lambda))) continue;
    const auto fit_start = Clock::now();
    fitted[c] = fit_sphere(shape_, members_[c], spheres_[c], lambda, options_.update);
    const auto projection_start = Clock::now();
    if (options_.project) fitted[c] = projector_->project(fitted[c].center);
    fit_seconds += std::chrono::duration<double>(projection_start - fit_start).count();
    projection_seconds += seconds_since(projection_start);
    if (pass_over_settled_) last_fits_[c] = {true, lambda, members_[c], spheres_[c], fitted[c]};
  }
  const double wall = seconds_since(start);
  const double busy = fit_seconds + projection_seconds;
  times_.update += busy > 0.0 ? wall * fit_seconds / busy : wall;
  times_.projection += busy > 0.0 ? wall * projection_seconds / busy : 0.0;
  std::vector<char> moved(count, 0);
  for (int c = 0; c < count; ++c) moved[c] = !same_sphere(fitted[c], spheres_[c]);
  spheres_ = std::move(fitted);
  return moved;
}

bool Skeletonizer::settled(int cluster, double lambda) const {
  const LastFit& last = last_fits_[cluster];
  const double tolerance = kSettledMove * shape_.diagonal;
  return last.made && last.lambda == lambda && same_sphere(spheres_[cluster], last.after) &&
         (last.after.center - last.before.center).norm() <= tolerance &&
         std::abs(last.after.radius - last.before.radius) <= tolerance &&
         members_[cluster] == last.members;
}

void Skeletonizer::check_target_fits(const Target& target) const {
  if (target.count() > shape_.size())
    throw InvalidOption("target.spheres", "must be at most the number of points (" +
                                       std::to_string(shape_.size()) + ", got " +
                                       std::to_string(target.count()) + ")");
}

int Skeletonizer::sphere_cap() const {
  // More spheres than points would leave clusters empty.
  return std::min(options_.max_spheres, shape_.size());
}

double Skeletonizer::worst_free_cluster_error() const {
  double worst = 0.0;
  for (std::size_t c = 0; c < spheres_.size(); ++c)
    if (!frozen_[c]) worst = std::max(worst, split_error(c));
  return worst;
}

bool Skeletonizer::misses_error_threshold() const {
  return worst_free_cluster_error() > std::pow(options_.target.error * shape_.diagonal, 2);
}

bool Skeletonizer::wants_more_spheres() const {
  const int count = static_cast<int>(spheres_.size());
  if (options_.target.count() > 0) return count < options_.target.count();
  return count < sphere_cap() && misses_error_threshold();
}

int Skeletonizer::split() {
  const auto start = Clock::now();
  const int count = static_cast<int>(spheres_.size());
  const int cap = options_.target.count() > 0 ? options_.target.count() : sphere_cap();
  // An error target may need thousands of spheres: it grows by the fraction alone. A large
  // count target grows by a share of the count too (below 200 spheres the share is under the
  // cap), or it would take a hundred rounds.
  const int per_round =
      options_.target.count() > 0
          ? std::max(options_.split.max_per_round, count / options_.split.large_count_share)
          : std::numeric_limits<int>::max();
  const int max_count = std::min(
      {static_cast<int>(std::ceil(options_.split.max_fraction * count)), per_round, cap - count});
  if (max_count <= 0) return 0;
  // With an error target, only clusters that still miss it may split (paper §3.4).
  const double threshold =
      options_.target.count() > 0 ? -1.0 : std::pow(options_.target.error * shape_.diagonal, 2);
  std::vector<bool> eligible(count);
  std::vector<double> rank(count);
  for (int c = 0; c < count; ++c) {
    eligible[c] =
        !frozen_[c] && static_cast<int>(members_[c].size()) >= 2 && split_error(c) > threshold;
    // Between E(C) (eq. 12), which the paper ranks by, and the worst vertex: ε is a Hausdorff
    // distance, and a well fitted cluster can still leave a tip uncovered. Their geometric mean
    // did best on the benchmark (docs/design.md, "Where vmas departs from the paper"). Both
    // weighted by the density ("Density").
    rank[c] = std::sqrt(split_error(c) * worst_errors_[c]);
  }
  // A perfectly fitted cluster (rank 0) must still be able to split when spheres are missing.
  const auto chosen = select_clusters_to_split(rank, cluster_adjacency(shape_, labels_, count),
                                               eligible, max_count);
  for (int c : chosen) {
    const int worst = worst_vertex(c);
    spheres_.push_back(projector_->ball_at(worst));
    frozen_.push_back(false);
    add_key();
  }
  times_.split += seconds_since(start);
  if (!chosen.empty()) repartition();
  return static_cast<int>(chosen.size());
}

void Skeletonizer::restart_schedule() {
  previous_error_ = total_error_;
  since_split_ = 0;
}

Turn Skeletonizer::advance() {
  Turn turn;
  turn.error = step();
  turn.converged =
      std::abs(previous_error_ - turn.error) <= options_.convergence * std::max(turn.error, 1e-300);
  previous_error_ = turn.error;
  ++since_split_;
  if (wants_more_spheres()) {
    if (turn.converged || since_split_ >= options_.split_interval) {
      turn.split = split();
      if (turn.split > 0)
        since_split_ = 0;
      else
        turn.done = turn.converged;  // nothing left that may be split
    }
  } else if (since_split_ >= options_.settle_iterations) {
    // Spheres may keep trading a few vertices for ever (paper §5): done after a while.
    turn.done = turn.converged || since_split_ >= options_.max_settle_iterations;
  }
  return turn;
}

RunSummary Skeletonizer::run(const ProgressCallback& progress) {
  RunSummary summary;
  const auto report = [&](Progress::Phase phase, double error, int round, int rounds,
                          double fraction) {
    summary.cancelled =
        progress && !progress(Progress{phase, summary.iterations, static_cast<int>(spheres_.size()),
                                       options_.target.count(), error, round, rounds, fraction});
    return !summary.cancelled;
  };
  const auto finish = [&] {
    summary.hit_max_iterations =
        summary.iterations == options_.max_iterations && !summary.converged;
    summary.spheres = static_cast<int>(spheres_.size());
    summary.error = total_error_;
    summary.error_threshold_missed = options_.target.count() == 0 && misses_error_threshold();
    return summary;
  };
  // After a coarse start, its settling is the first half of the phase (its growth is all of
  // Optimising).
  const bool coarse = start_coarse(progress, summary);
  if (summary.cancelled) return finish();
  restart_schedule();
  const double settled_before = coarse ? 0.5 : 0.0;
  double grown = coarse ? 1.0 : 0.0;  // Optimising's fraction: it never falls
  double first_worst = 0.0;  // with an error threshold: the worst cluster's error at first
  for (int iteration = summary.iterations + 1; iteration <= options_.max_iterations; ++iteration) {
    const Turn turn = advance();
    summary.iterations = iteration;
    const bool growing = turn.split > 0 || wants_more_spheres();
    // When growth ends (the count or the threshold met, or the sphere cap), the phase is done.
    if ((growing || grown < 1.0) &&
        !report(Progress::Phase::Optimising, turn.error, 0, 0,
                grown = growing ? std::max(grown, growth_fraction(first_worst)) : 1.0))
      return finish();
    if (!growing &&
        !report(Progress::Phase::Settling, turn.error, since_split_,
                options_.max_settle_iterations,
                turn.done ? 1.0
                          : settled_before + (1.0 - settled_before) * since_split_ /
                                                 options_.max_settle_iterations))
      return finish();
    if (turn.done) {
      summary.converged = turn.converged;
      break;
    }
  }
  // The partition has settled; refits with a small λ let the spheres of extremities reach them
  // (paper Fig. 5: a small λ fits the features) and the projection keeps them medial. Later
  // rounds re-partition first, so that the vertices follow the moved spheres.
  summary.cancelled = !final_refits(progress, summary.iterations);
  return finish();
}

bool Skeletonizer::final_refits(const ProgressCallback& progress, int iteration) {
  const int rounds = options_.final_rounds;
  for (int round = 0; round < rounds; ++round) {
    final_refit(round);
    if (progress &&
        !progress(Progress{Progress::Phase::FinalRefit, iteration,
                           static_cast<int>(spheres_.size()), options_.target.count(),
                           total_error_, round + 1, rounds, double(round + 1) / rounds}))
      return false;
  }
  return true;
}

double Skeletonizer::growth_fraction(double& first_worst) const {
  if (options_.target.count() > 0)
    return std::min(1.0, double(spheres_.size()) / options_.target.count());
  const double worst = worst_free_cluster_error();
  const double threshold = std::pow(options_.target.error * shape_.diagonal, 2);
  if (first_worst == 0.0) first_worst = worst;
  if (worst <= threshold) return 1.0;
  if (first_worst <= threshold || worst >= first_worst) return 0.0;
  return std::log(first_worst / worst) / std::log(first_worst / threshold);
}

bool Skeletonizer::start_coarse(const ProgressCallback& progress, RunSummary& summary) {
  const std::size_t vertices = shape_.size();
  const std::size_t target = options_.target.count();
  const std::size_t budget = std::max(vertices / kCoarseShare, kCoarseVerticesPerSphere * target);
  if (!options_.coarse_start || target == 0 || spheres_.size() != 1 ||
      budget > kCoarseAtMost * vertices)
    return false;
  SkeletonizerOptions coarse_options = options_;
  coarse_options.coarse_start = false;
  coarse_options.final_rounds = 0;  // the full shape's steps follow
  Skeletonizer coarse(coarsen_shape(shape_, budget), coarse_options);
  // Its settling is the first half of the run's.
  const ProgressCallback halved = [&](const Progress& p) {
    Progress q = p;
    if (q.phase == Progress::Phase::Settling) q.fraction *= 0.5;
    return !progress || progress(q);
  };
  const RunSummary coarse_summary = coarse.run(halved);
  summary.cancelled = coarse_summary.cancelled;
  summary.iterations = coarse_summary.iterations;
  spheres_ = coarse.spheres();
  frozen_.assign(spheres_.size(), false);
  keys_ = coarse.keys_;
  next_key_ = coarse.next_key_;
  energies_current_ = false;
  repartition();
  times_ += coarse.times();
  return true;
}

void Skeletonizer::final_refit(int round) {
  if (round > 0) {
    repartition();
    // As in step(), but until every cluster is big enough (a few tries): no later step moves
    // a sphere left with a handful of vertices, and it would end up unconnected (an empty one
    // split the skeleton of noisy meshes). A try that leaves one tiny again has given it a ball
    // that wins no vertex: on noisy data the worst vertex can be one whose normal points the
    // wrong way, and its ball lies on the wrong side. Later tries pass over such donors.
    for (int attempt = 0; attempt < kFinalReseeds && reseed_tiny_clusters(attempt > 0); ++attempt)
      repartition();
  }
  refresh_errors(fit_and_project(options_.final_lambda));
}

void Skeletonizer::check_id(int id) const {
  if (id < 0 || id >= static_cast<int>(spheres_.size()))
    throw InvalidArgument("no sphere with id " + std::to_string(id) + " (there are " +
                        std::to_string(spheres_.size()) + ")");
}

int Skeletonizer::add_sphere_at(int vertex) {
  if (vertex < 0 || vertex >= shape_.size())
    throw InvalidArgument("no vertex with index " + std::to_string(vertex));
  return add_sphere(projector_->ball_at(vertex));
}

int Skeletonizer::add_sphere(const Sphere& sphere) {
  if (!sphere.center.allFinite() || !(sphere.radius >= 0.0 && std::isfinite(sphere.radius)))
    throw InvalidArgument("a sphere needs a finite centre and a finite, non-negative radius");
  spheres_.push_back(sphere);
  frozen_.push_back(false);
  add_key();
  repartition();
  return static_cast<int>(spheres_.size()) - 1;
}

void Skeletonizer::remove_sphere(int id) {
  check_id(id);
  if (spheres_.size() == 1) throw InvalidArgument("cannot remove the last sphere");
  spheres_.erase(spheres_.begin() + id);
  frozen_.erase(frozen_.begin() + id);
  keys_.erase(keys_.begin() + id);
  if (id < static_cast<int>(last_fits_.size())) last_fits_.erase(last_fits_.begin() + id);
  for (int& label : labels_) label = label == id ? -1 : (label > id ? label - 1 : label);
  energies_current_ = false;
  repartition();
}

int Skeletonizer::id_of(std::uint64_t key) const {
  const auto found = std::find(keys_.begin(), keys_.end(), key);
  return found == keys_.end() ? -1 : static_cast<int>(found - keys_.begin());
}

void Skeletonizer::freeze(int id, bool frozen) {
  check_id(id);
  frozen_[id] = frozen;
}

void Skeletonizer::set_target(const Target& target) {
  SkeletonizerOptions changed = options_;
  changed.target = target;
  changed.validate();
  check_target_fits(changed.target);
  options_ = changed;
}

void Skeletonizer::set_lambda(double lambda) {
  SkeletonizerOptions changed = options_;
  changed.lambda = lambda;
  changed.validate();
  options_ = changed;
  energies_current_ = false;  // E_v depends on λ
}

void Skeletonizer::set_density(std::vector<double> density) {
  if (!density.empty()) {
    try {
      check_density(density, shape_.points.size());
    } catch (const InvalidInput& e) {
      throw InvalidArgument(e.what());
    }
  }
  shape_.set_density(std::move(density));
  last_fits_.clear();  // the fit weighs its vertices by the density
  refresh_errors(!energies_current_);  // the clusters' densities and worst weighted errors
}

void Skeletonizer::restore(const SkeletonizerState& state) {
  const int count = static_cast<int>(state.spheres.size());
  if (count < 1 || static_cast<int>(state.frozen.size()) != count ||
      static_cast<int>(state.labels.size()) != shape_.size() ||
      std::any_of(state.labels.begin(), state.labels.end(),
                  [&](int label) { return label < 0 || label >= count; }))
    throw InvalidArgument("not a state of this skeletonizer's shape");
  spheres_ = state.spheres;
  partitioned_spheres_.clear();  // the state's labels were the best of other spheres
  frozen_ = state.frozen;
  labels_ = state.labels;
  if (static_cast<int>(state.keys.size()) == count) {
    keys_ = state.keys;
    for (std::uint64_t key : keys_) next_key_ = std::max(next_key_, key + 1);
  } else {
    keys_.clear();
    for (int id = 0; id < count; ++id) add_key();
  }
  rebuild_members();
  refresh_errors(true);
}

void Skeletonizer::rebuild_members() {
  members_.assign(spheres_.size(), {});
  for (int v = 0; v < shape_.size(); ++v) members_[labels_[v]].push_back(v);
}

MedialMesh Skeletonizer::adjacency_mesh() const {
  const int count = static_cast<int>(spheres_.size());
  return build_medial_mesh(spheres_, cluster_adjacency(shape_, labels_, count));
}

MedialMesh Skeletonizer::medial_mesh() const {
  return options_.open_cavities ? without_cavities(adjacency_mesh()) : adjacency_mesh();
}

}  // namespace vmas
