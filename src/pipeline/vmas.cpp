// The one-call API: every stage in the order the CLI has always run them.
#include "vmas/vmas.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/density_mean.hpp"
#include "core/kdtree.hpp"
#include "core/stopwatch.hpp"
#include "core/validate_member.hpp"
#include "eval/envelope.hpp"
#include "optimise/connectivity.hpp"
#include "optimise/topology.hpp"
#include "pipeline/validity.hpp"
#include "prepare/holes.hpp"
#include "prepare/normals.hpp"
#include "prepare/prepare.hpp"
#include "refine/refine.hpp"
#include "vmas/eval.hpp"
#include "vmas/io.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

#ifndef VMAS_VERSION_STRING
#error "VMAS_VERSION_STRING is set by CMakeLists.txt from the project's version"
#endif

namespace vmas {
ThreadCount::ThreadCount(int threads) {
#ifdef _OPENMP
  previous_ = omp_get_max_threads();
  // More threads than cores only wait for each other (1000 threads ran 13 times slower).
  if (threads > 0) omp_set_num_threads(std::min(threads, omp_get_num_procs()));
#else
  (void)threads;
#endif
}

ThreadCount::~ThreadCount() {
#ifdef _OPENMP
  omp_set_num_threads(previous_);
#endif
}

namespace {

using internal::Clock;
using internal::seconds_since;

// A measured error above this fraction of the diagonal is a warning (large-error).
constexpr double kLargeError = 0.05;

// outward_flux below this: most normals point inward (0 for flat data or random signs).
constexpr double kClearlyInward = -0.1;

// The checks whose failure leaves a usable but doubtful skeleton, after those that preparation
// already made (result.warnings).
std::vector<Warning> warnings_about(const Result& result) {
  std::vector<Warning> warnings;
  const MeshDefects& mesh = result.mesh_defects;
  if (mesh.boundary_edges > 0)
    warnings.push_back({"open-mesh", "the mesh is open (" + std::to_string(mesh.boundary_edges) +
                                         " edges on one face only): it bounds no volume, and "
                                         "the skeleton is only an approximation near the holes"});
  if (mesh.misoriented_edges > 0)
    warnings.push_back(
        {"misoriented-faces", "neighbouring faces disagree on which side is outside (" +
                                  std::to_string(mesh.misoriented_edges) +
                                  " edges): re-orient the mesh consistently"});
  warnings.insert(warnings.end(), result.warnings.begin(), result.warnings.end());
  // A mesh warning above already says why it encloses nothing.
  const std::vector<Hole>& holes = result.prepare.holes;
  const bool unenclosed = result.enclosure < MedialProjector::kEnclosed && warnings.empty();
  if (unenclosed || !holes.empty()) {
    char figure[32];
    std::string what;
    if (unenclosed) {
      std::snprintf(figure, sizeof figure, "%.2g", result.enclosure);
      what = std::string("the data does not enclose a volume (winding number ") + figure +
             " inside, 1 for a closed surface)";
    }
    if (!holes.empty()) {
      std::snprintf(figure, sizeof figure, "%.1f",
                    100.0 * holes.front().width / result.prepare.diagonal);
      what += (unenclosed ? "; it has " : "the data is open: it has ") +
              std::to_string(holes.size()) + (holes.size() == 1 ? " hole" : " holes") +
              ", the widest " + figure + " % of the diagonal across";
    }
    std::string why =
        ": the skeleton spans holes as if the surface went on across them, and can be far from "
        "the data there";
    if (unenclosed) {
      why = ": open or single-view scan, holes, ";
      // Smoothing folds a part thinner than its radius onto one sheet, which encloses nothing.
      if (result.prepare.mls_radius > 0.0) {
        std::snprintf(figure, sizeof figure, "%.1f",
                      100.0 * result.prepare.mls_radius / result.prepare.diagonal);
        why += std::string("inconsistently oriented normals, or parts thinner than the smoothing "
                           "radius (") +
               figure + " % of the diagonal) that it merged into one sheet";
      } else {
        why += "or inconsistently oriented normals";
      }
      why += "; the skeleton is only an approximation there";
    }
    warnings.push_back({"open-surface", what + why});
  }
  if (result.skeleton_components > result.input_components)
    warnings.push_back(
        {"split-skeleton", "the skeleton has " + std::to_string(result.skeleton_components) +
                               " components, the input " + std::to_string(result.input_components) +
                               ": a thin part may have lost its spheres; more spheres "
                               "(--spheres) usually join them"});
  // The medial axis of a solid has a loop per handle and no cavity (issue 50).
  const MedialTopology& topology = result.topology;
  const bool known = result.input_genus.known && result.input_genus.genus.size() == 1;
  const bool loops_differ = known && topology.loops != result.input_genus.genus.front();
  if (loops_differ || topology.cavities > 0) {
    std::string what = "the skeleton has " + std::to_string(topology.loops) + " loop" +
                       (topology.loops == 1 ? "" : "s") + " and " +
                       std::to_string(topology.cavities) + " cavit" +
                       (topology.cavities == 1 ? "y" : "ies");
    if (known)
      what += ", the input genus " + std::to_string(result.input_genus.genus.front());
    std::string remedy;
    if (topology.cavities > 0)
      remedy = "they were kept (--keep-cavities; options.run.open_cavities leaves out the "
               "triangles that close them)";
    if (loops_differ)
      remedy += std::string(remedy.empty() ? "" : "; ") +
                (topology.loops < result.input_genus.genus.front()
                     ? "more spheres (--spheres) usually open a missing loop (unless "
                       "--keep-loops, a closed mesh's triangles that fill one are left out "
                       "where their clusters meet nowhere: options.loops_to_genus)"
                     : "an extra loop is a ring of spheres around a tube: more spheres usually "
                       "close it, and unless --keep-loops a closed mesh's are filled "
                       "(options.loops_to_genus)");
    warnings.push_back({"topology-mismatch", what + ": " + remedy});
  }
  const InvalidSpheres& invalid = result.invalid_spheres;
  if (invalid.outside > 0 || invalid.radius_off > 0)
    warnings.push_back(
        {"invalid-spheres", std::to_string(invalid.outside) + " of " +
                                std::to_string(result.medial_mesh.spheres.size()) +
                                " sphere centres lie outside the closed input and " +
                                std::to_string(invalid.radius_off) +
                                " radii differ from the distance to its surface by more than 1 % "
                                "of the diagonal: those spheres are no medial balls"});
  if (result.measured_error > kLargeError) {
    char figure[32];
    std::snprintf(figure, sizeof figure, "%.2f", 100.0 * result.measured_error);
    warnings.push_back(
        {"large-error", std::string("the skeleton is ") + figure +
                            " % of the diagonal away from the data at its worst (two-sided "
                            "Hausdorff distance to the data as prepared, smoothed when noisy" +
                            (holes.empty() ? std::string("): ") : std::string(", its holes closed: ")) +
                            "more spheres (--spheres) or a smaller --lambda fit the shape closer"});
  }
  if (result.summary.error_threshold_missed)
    warnings.push_back(
        {"target-not-reached",
         "the error threshold was not reached: the run stopped at " +
             std::to_string(result.summary.spheres) + " spheres (" +
             (result.summary.hit_max_iterations ? std::string("--max-iterations")
                                                : std::string("--max-spheres, the number of "
                                                              "points, or no cluster could split")) +
             ")"});
  return warnings;
}

}  // namespace

const char* version() { return VMAS_VERSION_STRING; }

void Options::validate() const {
  if (threads < 0)
    throw InvalidOption("threads", "must be 0 or more (got " + std::to_string(threads) + ")");
  if (starts < 1 || starts > kMaxStarts)
    throw InvalidOption("starts", "must be between 1 and " + std::to_string(kMaxStarts) +
                                      " (got " + std::to_string(starts) + ")");
  internal::validate_member("run", run);
  internal::validate_member("shape", shape);
  internal::validate_member("prepare", prepare);
  internal::validate_member("refine", refine);
}

namespace {

// The most spheres a run with `run` can end with.
int spheres_at_most(const SkeletonizerOptions& run) {
  return run.target.count() > 0 ? run.target.count() : run.max_spheres;
}

// prepare_shape(), with the progress callback that skeletonize() honours while preparing.
PreparedShape prepare_with_progress(SurfaceInput input, const Options& options,
                                    const ProgressCallback& progress) {
  const auto start = Clock::now();
  PreparedShape prepared;
  prepared.run = options.run;
  // Preparing: `round` of `rounds` are the stages done: cleaning, those of prepare_surface, a
  // smoothed cloud's thinning, the shape, its normals turned.
  constexpr int kStages = 1 + kPrepareStages + 3;
  const auto preparing = [&](int done) {
    Progress now;
    now.phase = Progress::Phase::Preparing;
    now.target_spheres = prepared.run.target.count();
    now.round = done;
    now.rounds = kStages;
    now.fraction = double(done) / kStages;
    return !progress || progress(now);
  };
  int done = 0;
  const auto stage_done = [&] {
    if (!preparing(done++)) throw Cancelled();
  };
  stage_done();

  Result& result = prepared.result;
  SurfaceInput surface = std::move(input);
  if (!surface.density.empty()) check_density(surface.density, surface.points.size());
  result.clean = clean_surface(surface);
  if (surface.points.empty()) throw InvalidInput("no usable points");
  result.seconds.clean = seconds_since(start);
  if (surface.is_mesh()) result.mesh_defects = mesh_defects(surface.faces);
  result.input_genus = surface_genus(surface, result.mesh_defects);
  const bool normals_given = !surface.is_mesh() && surface.has_normals() &&
                             !options.prepare.estimate_normals && !options.prepare.orient_normals;
  stage_done();
  result.prepare = prepare_surface(surface, options.prepare, [&](int stage) {
    return preparing(done + stage - 1);
  });
  done += kPrepareStages;
  result.seconds.prepare = result.prepare.seconds;
  if (normals_given && result.prepare.normals_oriented) {
    const int percent = static_cast<int>(std::round(100.0 * result.prepare.normals_disagreement));
    result.warnings.push_back(
        {"normals-reoriented",
         "the file's normals had arbitrary signs (" + std::to_string(percent) +
             " % of neighbouring ones pointed opposite ways, as normals estimated elsewhere do): "
             "vmas oriented them outward (--orient-normals, options.prepare.orient_normals, always "
             "does)"});
  } else if (normals_given && outward_flux(surface.points, surface.normals) < kClearlyInward)
    result.warnings.push_back({"inward-normals",
                               "the file's normals point inward on the whole; --orient-normals "
                               "(options.prepare.orient_normals) re-orients them"});

  adapt_shrinking_ball(result.prepare, prepared.run.shrinking_ball);
  const auto shape_start = Clock::now();
  // A smoothed cloud runs on fewer points. Whether it encloses a volume is judged on all of them:
  // the estimate reads low next to parts thinner than the thinned points' spacing.
  const std::size_t needed =
      smoothed_points_needed(surface, result.prepare, spheres_at_most(prepared.run));
  if (!surface.is_mesh() && needed < surface.points.size()) {
    prepared.run.shrinking_ball.enclosure = MedialProjector::enclosure_of(
        build_shape(surface, options.shape), prepared.run.shrinking_ball);
    thin_smoothed_cloud(surface, result.prepare, needed);
  }
  stage_done();
  prepared.shape = build_shape(surface, options.shape);
  stage_done();
  if (turn_inside_out_normals(surface, result.prepare, prepared.shape) > 0)
    prepared.shape = build_shape(surface, options.shape);
  prepared.surface = std::move(surface);
  result.input_components = component_count(prepared.shape);
  result.seconds.shape = seconds_since(shape_start);
  stage_done();
  return prepared;
}

}  // namespace

namespace {

// The weight of a distance to or from each vertex of `shape` with a density: (d / d_max)², the
// square root of Shape::error_weight's, an energy's (EvalOptions::point_weights; empty without a
// density, or with a uniform one).
std::vector<double> distance_weights(const Shape& shape) {
  if (std::all_of(shape.error_weights.begin(), shape.error_weights.end(),
                  [](double w) { return w == 1.0; }))
    return {};
  std::vector<double> weights;
  for (double w : shape.error_weights) weights.push_back(std::sqrt(w));
  return weights;
}

}  // namespace

EvalOptions refinement_eval_options(const PreparedShape& prepared) {
  const PrepareReport& report = prepared.result.prepare;
  EvalOptions measure = refinement_eval_options(report.smoothed());
  if (prepared.surface.is_mesh())
    measure.max_input_points =
        smoothed_points_needed(prepared.surface, report, spheres_at_most(prepared.run));
  // An open scan is measured against what a solid can do: its openings closed by lids.
  measure.lid_points = lid_points(report.holes, prepared.surface.points, report.noise.spacing);
  return measure;
}

PreparedShape prepare_shape(SurfaceInput input, const Options& options,
                            const ProgressCallback& progress) {
  options.validate();
  const ThreadCount threads(options.threads);
  return prepare_with_progress(std::move(input), options, progress);
}

std::vector<int> input_labels(const std::vector<int>& kept, const std::vector<int>& stand_in,
                              const std::vector<int>& labels, std::size_t input_points) {
  std::vector<int> by_row(input_points, -1);
  for (std::size_t i = 0; i < stand_in.size(); ++i)
    if (stand_in[i] >= 0) by_row[kept[i]] = labels[stand_in[i]];
  return by_row;
}

InputRows::InputRows(const std::vector<int>& kept, const std::vector<int>& stand_in,
                     std::size_t rows, std::size_t vertices)
    : vertices_(vertices) {
  std::vector<int> vertex(vertices);
  std::iota(vertex.begin(), vertex.end(), 0);
  vertex_of_row_ = input_labels(kept, stand_in, vertex, rows);
}

std::vector<double> InputRows::by_vertex(const std::vector<double>& by_row) const {
  if (by_row.size() != vertex_of_row_.size())
    throw InvalidArgument(std::to_string(by_row.size()) + " values for " +
                          std::to_string(vertex_of_row_.size()) + " input rows");
  return internal::mean_density_by_group(by_row, vertex_of_row_, vertices_, 1.0);
}

std::vector<double> InputRows::by_row(const std::vector<double>& by_vertex) const {
  if (by_vertex.size() != vertices_)
    throw InvalidArgument(std::to_string(by_vertex.size()) + " values for " +
                          std::to_string(vertices_) + " vertices");
  std::vector<double> values;
  values.reserve(vertex_of_row_.size());
  for (int vertex : vertex_of_row_) values.push_back(vertex >= 0 ? by_vertex[vertex] : 1.0);
  return values;
}

namespace {

// One pass of the pipeline over `input`: the result, and the skeletonizer's state at its end.
struct Pass {
  Result result;
  SkeletonizerState state;
  // What the starts are ranked by: result.measured_error, or with a density that error weighed
  // by it (docs/design.md, "Density").
  double start_error = 0.0;
  bool start_error_weighted = false;
  // The triangles of result.medial_mesh whose clusters meet nowhere on the shape (sorted
  // spheres): those that may fill a handle's loop.
  std::vector<std::array<int, 3>> meeting_nowhere;
};

// What another start needs of `prepared`: all but its shape, which the start builds in its own
// frame, and the maps from the input's points to the shape's (input_labels() uses the first
// start's): on a big cloud these are more than the run's memory.
PreparedShape without_shape(PreparedShape& prepared) {
  PreparedShape copy;
  std::vector<int> kept = std::move(prepared.result.clean.kept);
  std::vector<int> stand_in = std::move(prepared.result.prepare.stand_in);
  copy.result = prepared.result;
  prepared.result.clean.kept = std::move(kept);
  prepared.result.prepare.stand_in = std::move(stand_in);
  copy.run = prepared.run;
  copy.surface = prepared.surface;
  return copy;
}

// `prepared` (without its shape) carried into its working frame turned `turn` times: another
// start of the optimisation, on the same prepared points.
PreparedShape turned(PreparedShape prepared, int turn, const Options& options) {
  const auto start = Clock::now();
  turn_working_frame(prepared.result.prepare, prepared.surface, turn);
  prepared.shape = build_shape(prepared.surface, options.shape);
  prepared.result.seconds.shape = seconds_since(start);
  return prepared;
}

// The optimisation, refinement and connectivity on `prepared` (the labels of the input's points
// are the caller's: see input_labels).
Pass run_pass(PreparedShape prepared, const Options& options, const ProgressCallback& progress) {
  const EvalOptions measure = refinement_eval_options(prepared);
  Pass pass;
  Result& result = pass.result;
  result = std::move(prepared.result);
  const SkeletonizerOptions run = prepared.run;
  // Its options are Options::run (a count more than the points is found here).
  const auto build = [&] {
    try {
      return Skeletonizer(std::move(prepared.shape), run);
    } catch (const InvalidOption& e) {
      throw e.within("run");
    }
  };
  Skeletonizer skeletonizer = build();
  // The refinement's evaluator needs only the surface: it is built beside the run (its time is
  // then hidden in the run's, or in the waiting for it at the refinement's start).
  std::future<std::unique_ptr<Evaluator>> evaluator;  // waits for the build when destroyed
  if (options.refine.max_moves > 0)
    evaluator = std::async(std::launch::async, [&surface = prepared.surface, measure] {
      return std::make_unique<Evaluator>(surface, measure);
    });
  result.summary = skeletonizer.run(progress);
  if (result.summary.cancelled) throw Cancelled();
  const auto refine_start = Clock::now();
  const std::unique_ptr<Evaluator> measurer =
      evaluator.valid() ? evaluator.get() : std::make_unique<Evaluator>(prepared.surface, measure);
  const FinishReport finish =
      finish_skeleton(skeletonizer, *measurer, options.refine, /*refitted=*/true, progress);
  if (finish.cancelled) throw Cancelled();
  if (options.refine.max_moves > 0) {
    result.refine = finish.refine;
    // The stage's time, waiting for the evaluator included, in both places it is reported.
    result.seconds.refine = result.refine.seconds = seconds_since(refine_start);
  }
  result.measured_error = finish.error;
  if (result.prepare.diagonal > 0.0) result.measured_error /= result.prepare.diagonal;
  // The count is a promise: a skeleton with fewer spheres is an error, not a result.
  if (run.target.count() > 0 && result.summary.spheres < run.target.count())
    throw InvalidInput("cannot place " + std::to_string(run.target.count()) + " spheres on " +
                       std::to_string(skeletonizer.shape().size()) + " usable points (placed " +
                       std::to_string(result.summary.spheres) + "); ask for fewer");

  const auto connectivity_start = Clock::now();
  // Every triangle until skeletonize() ends: the choice of a start and the check of the
  // smoothing measure what the refinement measured.
  const MedialMesh working_mesh = skeletonizer.adjacency_mesh();  // in the shape's frame
  result.medial_mesh = result.prepare.frame.to_input(working_mesh);
  // What open_missing_loops may take out, where a loop is missing (only a closed mesh's genus is
  // known); without_cavities keeps the loops, so this mesh's count is the written one's. A tunnel
  // through solid deeper than the skeleton's measured error would raise that error.
  if (result.input_genus.known &&
      medial_topology(result.medial_mesh).loops < result.input_genus.handles())
    pass.meeting_nowhere = where_tunnels_fit(
        triangles_meeting_nowhere(skeletonizer.shape(), skeletonizer.labels(), result.medial_mesh),
        skeletonizer.spheres(), skeletonizer.projector(), *measurer, finish.error);
  result.skeleton_components = component_count(result.medial_mesh);
  result.seconds.connectivity = seconds_since(connectivity_start);
  pass.start_error = result.measured_error;
  // The refinement measures unweighted (weighted, it let a sparse region's part go uncovered:
  // armadillo, 4 : 1 on its top, ε 3.35 -> 9.71 %); the start kept is the one that serves the
  // density best.
  std::vector<double> weights = distance_weights(skeletonizer.shape());
  if (options.starts > 1 && !weights.empty() && result.prepare.diagonal > 0.0) {
    const auto weighing_start = Clock::now();
    EvalOptions weighted = measure;
    weighted.point_weights = std::move(weights);
    pass.start_error =
        evaluate(prepared.surface, working_mesh, weighted).hausdorff /
        result.prepare.diagonal;
    pass.start_error_weighted = true;
    result.seconds.refine += seconds_since(weighing_start);  // a measurement, as the refinement's
  }
  // A mesh without boundary, non-manifold or misoriented edges bounds a volume: its winding
  // number is exactly 1 inside, however long and thin its triangles (the estimate from the
  // vertices' areas and normals is not, next to such triangles).
  result.enclosure = prepared.surface.is_mesh() && result.mesh_defects.closed()
                         ? 1.0
                         : skeletonizer.projector().enclosure();
  // Inside and the distance to the surface say something of a sphere only on a closed input.
  const bool closed = prepared.surface.is_mesh()
                          ? result.mesh_defects.closed()
                          : result.enclosure >= MedialProjector::kEnclosed &&
                                result.prepare.holes.empty();
  if (closed)
    result.invalid_spheres = invalid_spheres(skeletonizer.spheres(), skeletonizer.projector(),
                                             *measurer, result.prepare.diagonal);

  result.seconds += skeletonizer.times();
  pass.state = skeletonizer.state();
  return pass;
}

// The OpenMP threads a call may use: options.threads, or OpenMP's default team.
int thread_budget(int threads) {
#ifdef _OPENMP
  return threads > 0 ? std::min(threads, omp_get_num_procs()) : omp_get_max_threads();
#else
  (void)threads;
  return 1;
#endif
}

// How far one pass is, from its progress in one of its phases (Preparing to Refining): the
// phases' rough shares of a pass's time, so that the fraction rises once over the pass.
double pass_fraction(const Progress& p) {
  constexpr double kPhaseEnds[] = {0.1, 0.5, 0.7, 0.75, 1.0};
  const int phase = static_cast<int>(p.phase);
  if (phase > static_cast<int>(Progress::Phase::Refining))
    throw std::logic_error("pass_fraction: not a phase of one pass");
  const double from = phase == 0 ? 0.0 : kPhaseEnds[phase - 1];
  return from + (kPhaseEnds[phase] - from) * p.fraction;
}

// How often the calling thread reports the other starts' progress while it waits for them.
constexpr auto kWaitReportInterval = std::chrono::milliseconds(100);

// run_pass() on `prepared` in each of options.starts turns of the working frame: the pass with
// the least measured error (the first among equals) among those whose skeleton has no more
// pieces than the input. With a thread for
// each, the starts run side by side (the optimisation's serial parts leave cores idle: two starts
// took 1.3-1.5 times one start's time, against 2 one after the other); the calling thread runs
// the first and reports its progress, then the others' (Phase::OtherStarts; only the calling
// thread calls `progress`), and the others stop when it is cancelled.
Pass best_of_starts(PreparedShape prepared, std::size_t input_points, const Options& options,
                    const ProgressCallback& progress) {
  const int threads = thread_budget(options.threads);
  const bool side_by_side = options.starts > 1 && threads >= options.starts;
  const int threads_per_start = side_by_side ? threads / options.starts : threads;
  std::atomic<bool> stop{false};
  struct Run {
    Pass pass;
    double seconds = 0.0;
  };
  // The first start runs on `prepared` itself, so the others take their copies first.
  std::vector<PreparedShape> sources;
  for (int start = 1; start < options.starts; ++start) sources.push_back(without_shape(prepared));
  const auto run_start = [&](int start, const ProgressCallback& report) {
    const ThreadCount count(threads_per_start);
    const auto start_time = Clock::now();
    Run run{run_pass(start == 0 ? std::move(prepared)
                                : turned(std::move(sources[start - 1]), start, options),
                     options, report)};
    run.seconds = seconds_since(start_time);
    return run;
  };
  const auto report = [&](const Progress& p) {
    if (!stop && progress && !progress(p)) stop = true;
    return !stop;
  };
  const auto report_other = [&](int start, const Progress& inner) {
    Progress p = inner;
    p.phase = Progress::Phase::OtherStarts;
    p.round = start + 1;
    p.rounds = options.starts;
    p.fraction = (start - 1 + pass_fraction(inner)) / (options.starts - 1);
    return report(p);
  };
  // Side by side, each other start leaves its last progress here for the calling thread.
  std::mutex latest_mutex;
  std::vector<Progress> latest(options.starts);
  std::vector<std::future<Run>> others;
  if (side_by_side)
    for (int start = 1; start < options.starts; ++start)
      others.push_back(std::async(std::launch::async, run_start, start,
                                  [&, start](const Progress& p) {
                                    const std::lock_guard<std::mutex> lock(latest_mutex);
                                    latest[start] = p;
                                    return !stop;
                                  }));
  std::vector<Run> runs;
  try {
    runs.push_back(run_start(0, report));
    for (int start = 1; start < options.starts; ++start) {
      if (!side_by_side) {
        runs.push_back(run_start(start, [&](const Progress& p) { return report_other(start, p); }));
        continue;
      }
      while (others[start - 1].wait_for(kWaitReportInterval) != std::future_status::ready)
        report_other(start, [&] {
          const std::lock_guard<std::mutex> lock(latest_mutex);
          return latest[start];
        }());
      runs.push_back(others[start - 1].get());
    }
    if (options.starts > 1) {  // done: a cancellation now would cost the work, not save it
      Progress last_pass_ended;
      last_pass_ended.phase = Progress::Phase::Refining;
      last_pass_ended.fraction = 1.0;
      report_other(options.starts - 1, last_pass_ended);
    }
  } catch (...) {
    stop = true;
    for (auto& other : others)
      if (other.valid()) other.wait();
    throw;
  }
  // A skeleton in more pieces than the input is wrong whatever its error (split-skeleton).
  const auto rank = [&](std::size_t k) {
    const Result& r = runs[k].pass.result;
    return std::make_pair(r.skeleton_components > r.input_components, runs[k].pass.start_error);
  };
  std::vector<double> errors;
  std::size_t best = 0;
  double others_seconds = 0.0;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    errors.push_back(runs[k].pass.start_error);
    if (rank(k) < rank(best)) best = k;
    others_seconds += runs[k].seconds;
  }
  others_seconds -= runs[best].seconds;
  Pass kept = std::move(runs[best].pass);
  const Result& maps = best == 0 ? kept.result : runs[0].pass.result;
  kept.result.labels =
      input_labels(maps.clean.kept, maps.prepare.stand_in, kept.state.labels, input_points);
  if (best != 0) {
    kept.result.clean.kept = std::move(runs[0].pass.result.clean.kept);
    kept.result.prepare.stand_in = std::move(runs[0].pass.result.prepare.stand_in);
  }
  kept.result.start_kept = static_cast<int>(best);
  kept.result.start_errors = std::move(errors);
  kept.result.start_errors_weighted = kept.start_error_weighted;
  // Side by side, the other starts' time is hidden in this one's.
  kept.result.seconds.other_starts = side_by_side ? 0.0 : others_seconds;
  return kept;
}

// The input prepared once, and the best of its starts.
Pass best_start(const SurfaceInput& input, const Options& options,
                const ProgressCallback& progress) {
  return best_of_starts(prepare_with_progress(input, options, progress), input.points.size(),
                        options, progress);
}

// The smoothing a noise estimate calls for can also erase what it should keep: parts of a cloud
// thinner than the smoothing radius merge, normals flip, and balls grow out of the shape; the
// outlier filter and the fringe trim take a sparse thin part away with the noise's tails. Such a
// skeleton reaches far past the data, or lies far from some of it, so a second pass skeletonizes
// the points as they are (--denoise off), and both skeletons are measured against those points
// (docs/noise.md, step 5, has what it decides on the benchmark). A mesh's smoothing follows its
// faces and merges nothing: it is not checked.

// A part lost to the smoothing: input points farther from the skeleton than the measured error
// plus this many noise deviations (a noise tail, at most 4.7 on the benchmark's 96 noisy clouds;
// a lost part 9-39 on sparse clouds with thin parts) ...
constexpr double kLostPartNoises = 6.0;
// ... each with this many others as far within this many spacings (strays are alone).
constexpr int kLostPartNeighbours = 2;
constexpr double kLostPartReach = 3.0;
// The share of Progress::Phase::SmoothingCheck that looking for a lost part takes (the rest is
// the second pass, when there is one).
constexpr double kLostPartShare = 0.1;

// The noise measured on a prepared input, as a fraction of its diagonal.
double noise_fraction(const PrepareReport& prepared) {
  return prepared.diagonal > 0.0 ? prepared.noise.sigma / prepared.diagonal : 0.0;
}

// The input's points that cleaning kept, in the input's coordinates, less the stray clusters:
// the points as they are.
SurfaceInput points_as_they_are(const SurfaceInput& input, const Result& result) {
  const std::vector<int>& strays = result.prepare.stray_points;
  SurfaceInput points;
  points.points.reserve(result.clean.kept.size() - strays.size());
  auto stray = strays.begin();
  for (std::size_t j = 0; j < result.clean.kept.size(); ++j) {
    if (stray != strays.end() && *stray == static_cast<int>(j)) {
      ++stray;
      continue;
    }
    points.points.push_back(input.points[result.clean.kept[j]]);
  }
  return points;
}

// Whether input points as they are (`points`) that the skeleton of `smoothed` lies far from are
// next to one another: a part the smoothing took away. `go_on` as points_farther_than's.
bool lost_a_part(const Result& smoothed, const SurfaceInput& points,
                 const std::function<bool(double)>& go_on) {
  const PrepareReport& prepared = smoothed.prepare;
  if (!(prepared.diagonal > 0.0)) return false;
  Box bounds;
  for (const Vec3& p : points.points) bounds.extend(p);
  const double far = bounds.diagonal().norm() *
                     (smoothed.measured_error + kLostPartNoises * noise_fraction(prepared));
  std::vector<Vec3> far_points;
  for (int i : points_farther_than(smoothed.medial_mesh, points.points, far, go_on))
    far_points.push_back(points.points[i]);
  if (far_points.size() <= static_cast<std::size_t>(kLostPartNeighbours)) return false;
  const KdTree tree(far_points);
  const double reach = kLostPartReach * prepared.noise.spacing * prepared.frame.scale;
  std::vector<int> neighbours;
  std::vector<double> squared;
  for (const Vec3& p : far_points) {
    tree.k_nearest(p, kLostPartNeighbours + 1, neighbours, squared);
    if (squared.back() <= reach * reach) return true;
  }
  return false;
}

// `points`: the input's points as they are; `smoothed_seconds`: the time of the smoothed pass.
// The time of the pass that is not kept, and the judging, are the check's.
void check_smoothing(Pass& smoothed, double smoothed_seconds, const SurfaceInput& input,
                     const SurfaceInput& points, const Options& options,
                     const ProgressCallback& progress) {
  const auto start = Clock::now();
  Options as_they_are = options;
  as_they_are.prepare.denoise = PrepareOptions::Denoise::Off;
  // The pass is the rest of the phase: the first start's share of it, then the other starts'.
  const int starts = options.starts;
  const ProgressCallback checking = [&](const Progress& inner) {
    if (!progress) return true;
    Progress p = inner;
    p.phase = Progress::Phase::SmoothingCheck;
    const double pass = inner.phase == Progress::Phase::OtherStarts
                            ? (1.0 + (starts - 1) * inner.fraction) / starts
                            : pass_fraction(inner) / starts;
    p.fraction = kLostPartShare + (1.0 - kLostPartShare) * pass;
    return progress(p);
  };
  Pass unsmoothed = best_start(input, as_they_are, checking);
  const double unsmoothed_seconds = seconds_since(start);
  const auto judging_start = Clock::now();
  EvalOptions reach;
  reach.surface_samples = 0;
  reach.maxima_only = true;
  Evaluator judge(points, reach);
  const EvalResult smoothed_fit = judge(smoothed.result.medial_mesh);
  const EvalResult unsmoothed_fit = judge(unsmoothed.result.medial_mesh);
  SmoothingCheck check;
  check.made = true;
  const double diagonal = smoothed_fit.diagonal;
  check.smoothed_reach = smoothed_fit.medial_to_surface_max / diagonal;
  check.unsmoothed_reach = unsmoothed_fit.medial_to_surface_max / diagonal;
  check.smoothed_cover = smoothed_fit.surface_to_medial_max / diagonal;
  check.unsmoothed_cover = unsmoothed_fit.surface_to_medial_max / diagonal;
  // Both are measured against noisy points: a difference within their noise tells nothing, and
  // the noise's own tails lie some deviations from any skeleton.
  const double noise = noise_fraction(smoothed.result.prepare);
  check.smoothing_kept = check.smoothed_reach <= check.unsmoothed_reach + noise &&
                         check.smoothed_cover <= check.unsmoothed_cover + kLostPartNoises * noise;
  const double judging = seconds_since(judging_start);
  if (!check.smoothing_kept) {
    unsmoothed.result.prepare.noise = smoothed.result.prepare.noise;  // as measured
    smoothed = std::move(unsmoothed);
  }
  smoothed.result.smoothing_check = check;
  smoothed.result.seconds.smoothing_check +=
      (check.smoothing_kept ? unsmoothed_seconds : smoothed_seconds) + judging;
}

}  // namespace

BestStart best_start(const PreparedShape& prepared, const Options& options,
                     const ProgressCallback& progress) {
  options.validate();
  const ThreadCount threads(options.threads);
  // (The passes' labels of the input's points are not used: any count that holds them will do.)
  const std::vector<int>& kept = prepared.result.clean.kept;
  Pass pass = best_of_starts(prepared, kept.empty() ? 0 : kept.back() + 1, options, progress);
  // A turned start's spheres, back into the frame of `prepared` (the turn is a rotation).
  const Frame& kept_frame = pass.result.prepare.frame;
  const Frame& frame = prepared.result.prepare.frame;
  for (Sphere& sphere : pass.state.spheres) {
    sphere.center = frame.to_working(kept_frame.to_input(sphere.center));
    sphere.radius *= kept_frame.scale / frame.scale;
  }
  pass.state.keys.clear();
  return {std::move(pass.state), pass.result.measured_error};
}

Result skeletonize(SurfaceInput input, const Options& options, const ProgressCallback& progress) {
  options.validate();
  const ThreadCount threads(options.threads);
  const auto start = Clock::now();
  const bool may_check =
      options.prepare.denoise == PrepareOptions::Denoise::Auto && !input.is_mesh();
  const std::size_t input_points = input.points.size();
  PreparedShape prepared =
      prepare_with_progress(may_check ? input : std::move(input), options, progress);
  // Only the check of a smoothing reads the input again: otherwise its memory goes now (on a big
  // cloud it is more than the run's).
  if (!(may_check && prepared.result.prepare.smoothed())) input = SurfaceInput{};
  Pass pass = best_of_starts(std::move(prepared), input_points, options, progress);
  if (may_check && pass.result.prepare.smoothed()) {
    const double smoothed_seconds = seconds_since(start);
    const auto judging_start = Clock::now();
    const SurfaceInput points = points_as_they_are(input, pass.result);
    const auto checking = [&](double fraction) {
      Progress p;
      p.phase = Progress::Phase::SmoothingCheck;
      p.fraction = fraction;
      return !progress || progress(p);
    };
    const bool check = pass.result.measured_error > kLargeError ||
                       lost_a_part(pass.result, points, [&](double searched) {
                         return checking(kLostPartShare * searched);
                       });
    pass.result.seconds.smoothing_check = seconds_since(judging_start);
    if (check) check_smoothing(pass, smoothed_seconds, input, points, options, progress);
    checking(1.0);  // done: a cancellation now would cost the work, not save it
  }
  Result result = std::move(pass.result);
  if (options.run.open_cavities) result.medial_mesh = without_cavities(std::move(result.medial_mesh));
  if (options.loops_to_genus && result.input_genus.known) {
    const int loops = result.input_genus.handles();
    result.medial_mesh = open_missing_loops(std::move(result.medial_mesh), loops,
                                            pass.meeting_nowhere, &result.loops_opened);
    result.medial_mesh =
        fill_extra_loops(std::move(result.medial_mesh), loops, &result.loops_filled);
  }
  result.topology = medial_topology(result.medial_mesh);
  result.warnings = warnings_about(result);
  result.seconds.total = seconds_since(start);
  return result;
}

}  // namespace vmas
