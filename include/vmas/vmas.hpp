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

#include "vmas/error.hpp"
#include "vmas/eval.hpp"
#include "vmas/options.hpp"
#include "vmas/skeletonizer.hpp"
#include "vmas/types.hpp"

#pragma GCC visibility push(default)  // what the public headers declare is exported

namespace vmas {

// The version of the library this program runs with (e.g. "0.4.0": project()'s VERSION in
// CMakeLists.txt).
const char* version();

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
  int loops_filled = 0;         // extra loops filled (Options::loops_to_genus)
  int loops_opened = 0;         // missing loops opened (Options::loops_to_genus)
  InvalidSpheres invalid_spheres;
  double measured_error = 0.0;  // the skeleton's two-sided Hausdorff distance to the prepared
                                // data, its holes closed by lids (the refinement's measure),
                                // fraction of its diagonal
  SmoothingCheck smoothing_check;
  // measured_error of every start, in order (Options::starts); with start_errors_weighted, that
  // error with each distance weighed by the density (more than one start, a field that is not
  // uniform), which the start kept is chosen by (docs/design.md, "Density").
  std::vector<double> start_errors;
  bool start_errors_weighted = false;
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
// its smoothing, on a smoothed mesh about smoothed_points_needed() of its vertices, and on a
// cloud with holes lids across them (EvalOptions::lid_points).
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

// Density (SurfaceInput::density; docs/design.md, "Density"). Throws InvalidInput naming the
// first problem when `density` is not one finite value >= 0 per point of `points`, or all 0.
void check_density(const std::vector<double>& density, std::size_t points);

// A density for the points of `surface` (as stored, in its coordinates) by a rule:
//   "curvature": 1 where the surface is flattest, rising with the surface variation of a point's
//     16 nearest neighbours (the least of their spread's eigenvalues over the sum) to 4 at the
//     5 % most curved points: sharp edges and small features of a part get finer;
//   "distance-to:X,Y,Z,R[,D]": D (4 unless given) within R of the point (X, Y, Z), 1 elsewhere.
// Points with a NaN coordinate get 1. Throws InvalidOption ("density") for another rule.
std::vector<double> density_by_rule(const SurfaceInput& surface, const std::string& rule);
// Whether `text` names one of those rules (well formed or not), rather than a file.
bool is_density_rule(const std::string& text);

// What the stage measures with: coarser than vmas eval's defaults (the input's vertices only, 4x
// the boundary spacing, 8 refined maxima, maxima only), and a cloud's gaps measured across its
// points' tangent discs (EvalOptions::cloud_as_discs: a sparse sampling's gaps are no error)
// unless the cloud is `smoothed` (PrepareReport::smoothed: the smoothed surface's normals round
// its edges off, and discs there would hide spheres reaching past them, as on a noisy gear's
// teeth). Its Evaluator takes a while to build (a tree over the input's faces) and needs only
// the surface: vmas::skeletonize builds it beside the run and hands it to the overload below.
EvalOptions refinement_eval_options(bool smoothed = false);

// The end of every run, as vmas::skeletonize, EditSession::finish and Python's
// Skeletonizer.finish make it: the final refits (Skeletonizer::final_refit, options().final_rounds;
// Phase::FinalRefit after each) unless the run made them already (`refitted`: Skeletonizer::run
// does), then the refinement (when options.max_moves > 0), and the error measured with
// `evaluator` (the refinement's last measurement, or one of its own).
FinishReport finish_skeleton(Skeletonizer& skeletonizer, Evaluator& evaluator,
                             const RefineOptions& options, bool refitted,
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
