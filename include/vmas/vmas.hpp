#pragma once
// The one-call API: a surface in, a skeleton out, doing exactly what `vmas skeletonize` does —
// cleaning, outlier removal and denoising, normal estimation and orientation, the optimisation
// and its final refits, and the checks that turn into warnings. No PCL in this header; users of
// PCL types include vmas/pcl.hpp.
//
//   vmas::Options options;
//   options.run.target.spheres = 40;
//   const vmas::Result result = vmas::skeletonize(surface, options);
//   vmas::write_medial_mesh("skeleton.ply", result.medial_mesh);
//
// Thread-safe: calls from several threads do not share state (each sets its own thread count).
#include <string>
#include <vector>

#include "vmas/clean.hpp"
#include "vmas/error.hpp"
#include "vmas/prepare.hpp"
#include "vmas/refine.hpp"
#include "vmas/shape.hpp"
#include "vmas/skeletonizer.hpp"
#include "vmas/topology.hpp"
#include "vmas/types.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

// The version of the library this program runs with (e.g. "0.4.0": project()'s VERSION in
// CMakeLists.txt).
const char* version();

// Every option of `vmas skeletonize`, with its defaults.
constexpr int kMaxStarts = 8;

struct Options {
  int threads = 0;          // OpenMP threads of this call (0: OpenMP's default, all cores)
  int starts = 2;           // optimisations, each in its own turn of the working frame
                            // (turn_working_frame), at most kMaxStarts; the one with the least
                            // measured error whose skeleton has no more pieces than the input is
                            // the result. The optimisation is a local search
                            // that rounding sends elsewhere: two starts make a poor result rarer
                            // (1: less time)
  PrepareOptions prepare;   // denoising (auto), outliers, normal estimation and orientation
  ShapeOptions shape;       // k of a cloud's neighbour graph
  SkeletonizerOptions run;  // the target (run.target: spheres or error), λ, final refits,
                            // convergence, shrinking balls, ...
  RefineOptions refine;     // worst-case refinement after the run (max_moves 0: off)
  // Throws InvalidOption naming the option; option() gives its CLI name.
  void validate() const;
};

// Something about the input or the result the caller should know; the result is still usable.
struct Warning {
  // A stable identifier, for programs: "open-surface", "open-mesh", "misoriented-faces",
  // "inward-normals", "normals-reoriented" (a cloud's normals of arbitrary sign, oriented),
  // "split-skeleton", "topology-mismatch" (loops other than the input's genus, or cavities),
  // "large-error" (measured ε above 5 % of the diagonal),
  // "target-not-reached" (an error threshold stopped at the sphere cap).
  std::string code;
  std::string message;  // one line, for people
};


// When the noise of a cloud was smoothed and the skeleton came out far from the data
// (large-error), or a part of the data lies far from it (the smoothing took a thin part away),
// the points were skeletonized a second time as they are (--denoise off), and both skeletons
// measured against them: the smoothed one is the result unless the other reaches less far past
// them by more than the noise, or comes nearer their farthest point by far more (lengths:
// fraction of the diagonal).
struct SmoothingCheck {
  bool made = false;
  bool smoothing_kept = true;     // false: the result is that of the unsmoothed points
  double smoothed_reach = 0.0;    // medial -> data maximum of the smoothed points' skeleton
  double unsmoothed_reach = 0.0;  // and of the unsmoothed points' skeleton
  double smoothed_cover = 0.0;    // data -> medial maximum of the smoothed points' skeleton
  double unsmoothed_cover = 0.0;  // and of the unsmoothed points' skeleton
};

// Spheres that a closed input shows to be no medial balls (invalid_spheres in src/pipeline/validity.hpp):
// counted only when the input encloses a volume (a mesh without defects, or a cloud whose
// winding number reads closed and that has no holes).
struct InvalidSpheres {
  bool checked = false;        // the input is closed, so the counts below mean something
  std::size_t outside = 0;     // centres whose winding number is at most ½
  std::size_t radius_off = 0;  // radii further than 1 % of the diagonal from the centre's
                               // distance to the surface
};

struct Result {
  MedialMesh medial_mesh;   // in the input's coordinates
  std::vector<int> labels;  // one per input point: the sphere whose cluster holds it; -1 for a
                            // point dropped (NaN, duplicate, outlier, vertex of no face)
  RunSummary summary;
  RefineReport refine;       // what the worst-case refinement tried and kept
  CleanReport clean;         // what cleaning removed (clean.kept: input index of each point kept)
  PrepareReport prepare;     // outliers, noise, smoothing, normals, the working frame
  MeshDefects mesh_defects;  // meshes: boundary, non-manifold and misoriented edges
  double enclosure = 0.0;    // median winding number inside (1: a closed surface; exactly 1
                             // for a mesh without boundary, non-manifold or misoriented edges)
  int input_components = 0;  // of the shape's neighbour graph (mesh edges or k-NN graph)
  int skeleton_components = 0;  // of the medial mesh
  SurfaceGenus input_genus;     // meshes: the genus of each piece, when known
  MedialTopology topology;      // of the medial mesh: pieces, loops, cavities
  InvalidSpheres invalid_spheres;
  double measured_error = 0.0;  // the skeleton's two-sided Hausdorff distance to the prepared
                                // data (the refinement's measure), fraction of its diagonal
  SmoothingCheck smoothing_check;
  std::vector<double> start_errors;  // measured_error of every start, in order (Options::starts)
  int start_kept = 0;                // which of them is the result
  Timings seconds;
  std::vector<Warning> warnings;
};

// The first half of skeletonize(): the shape the optimisation runs on (cleaned, thinned,
// denoised, with normals, in the working frame result.prepare.frame) and the run's options
// adapted to what preparation found. For front ends that drive a Skeletonizer or an
// EditSession themselves. `result` holds clean, prepare, mesh_defects, input_components and
// the seconds of those stages. Throws as skeletonize() does.
struct PreparedShape {
  Shape shape;
  SurfaceInput surface;  // what `shape` was built from (same frame): what the result is measured on
  SkeletonizerOptions run;
  Result result;
};
// `progress` as skeletonize() calls it while preparing (Phase::Preparing, round of rounds:
// the stages done); returning false cancels (throws Cancelled).
PreparedShape prepare_shape(SurfaceInput input, const Options& options = {},
                            const ProgressCallback& progress = {});

// The label of each of the `input_points` rows of the input a shape was prepared from: its
// stand-in's among the prepared shape's vertices (`labels`, by vertex), −1 for a row that
// cleaning or preparation dropped. `kept` and `stand_in`: the preparation's result.clean.kept
// and result.prepare.stand_in.
std::vector<int> input_labels(const std::vector<int>& kept, const std::vector<int>& stand_in,
                              const std::vector<int>& labels, std::size_t input_points);

// Between the input's rows and a prepared shape's vertices, for values given by row (a density
// file, Python's density=) and shown by vertex: each vertex takes the mean of the rows it stands
// for (1 when none does: a sampled mesh's new vertices), each row its vertex's (1 for a row that
// cleaning or preparation dropped). `kept` and `stand_in` as input_labels takes them.
class InputRows {
 public:
  InputRows() = default;
  InputRows(const std::vector<int>& kept, const std::vector<int>& stand_in, std::size_t rows,
            std::size_t vertices);
  std::vector<double> by_vertex(const std::vector<double>& by_row) const;  // one value per row
  std::vector<double> by_row(const std::vector<double>& by_vertex) const;  // one per vertex
  std::size_t rows() const { return vertex_of_row_.size(); }

 private:
  std::vector<int> vertex_of_row_;  // −1: dropped
  std::size_t vertices_ = 0;
};
// What skeletonize()'s refinement measures a prepared shape with: refinement_eval_options() of
// its smoothing, and on a smoothed mesh about smoothed_points_needed() of its vertices.
EvalOptions refinement_eval_options(const PreparedShape& prepared);

// What skeletonize() keeps of the runs on a prepared shape: its starts (options.starts, side by
// side), each with the final refits and the refinement, and the best (without the check of the
// smoothing, which needs the input). The state of a Skeletonizer on `prepared.shape` (in its
// frame, whichever start it came from; new keys) and its measured two-sided error / diagonal.
// Runs with prepared.run (options.run is not read). Throws as skeletonize() does.
struct BestStart {
  SkeletonizerState state;
  double measured_error = 0.0;
};
BestStart best_start(const PreparedShape& prepared, const Options& options,
                     const ProgressCallback& progress = {});

// The OpenMP thread count of the calling thread while it lives (0: left as it is; never more than
// the cores: more only wait for each other). OpenMP keeps the count per thread, so calls from
// other threads are not affected.
class ThreadCount {
 public:
  explicit ThreadCount(int threads);
  ~ThreadCount();
  ThreadCount(const ThreadCount&) = delete;
  ThreadCount& operator=(const ThreadCount&) = delete;

 private:
  int previous_ = 0;
};

// Skeletonizes `input` (a mesh, or a cloud with or without normals; NaN points allowed), taken
// by value: std::move a surface you no longer need to spare a copy of a big scan.
// `progress` is called once while preparing and after every step and final refit, from the
// calling thread; returning false cancels (throws Cancelled). Throws InvalidOption for bad
// options, InvalidInput for data that cannot give the skeleton asked for (too few usable
// points, a count that cannot be met).
Result skeletonize(SurfaceInput input, const Options& options = {},
                   const ProgressCallback& progress = {});

}  // namespace vmas

#pragma GCC visibility pop
