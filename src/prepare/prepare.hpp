#pragma once
// Turns a cleaned input into what the skeletonizer needs: outliers removed, scan noise measured
// and smoothed away, normals estimated and oriented. What a front end would otherwise have to
// repeat; the CLI is one caller.
#include <cstddef>
#include <functional>

#include "vmas/options.hpp"
#include "vmas/types.hpp"

namespace vmas {

// Prepares `surface` in place (see above). The points are first moved to a working frame
// (report.frame; map results back with Frame::to_input): their centroid at the origin, their
// principal axes along x, y, z, the bounding-box diagonal kept, a power-of-two scale for data of
// extreme size. So no stage loses precision to an offset (georeferenced scans), and the skeleton
// does not depend on how the data was placed: the same shape rotated, moved or scaled gives the
// same skeleton, rotated, moved and scaled with it. A clean mesh is left as it is unless it is too
// coarse for the method (its faces are then sampled: sample_coarse_mesh); a noisy one has
// its vertices smoothed along its faces (smooth_mesh) and stays a mesh. Throws InvalidInput when
// too few points remain.
// `keep_going` (optional) is called between stages, so that a long preparation can be stopped
// (vmas::Cancelled is thrown when it returns false) and followed: its argument is the stages
// done so far, of kPrepareStages.
constexpr int kPrepareStages = 8;
PrepareReport prepare_surface(SurfaceInput& surface, const PrepareOptions& options,
                              const std::function<bool(int)>& keep_going = {});

// How many of a prepared surface's points a run of `spheres` spheres needs: a smoothed surface
// holds no detail finer than its noise, and its points about 0.7 noises apart are enough, but no
// fewer than 50 per sphere; every point otherwise (a clean surface, or spheres 0: not known). A
// smoothed cloud is thinned to them (thin_smoothed_cloud); a smoothed mesh keeps its vertices,
// and the refinement measures on that many (EvalOptions::max_input_points).
std::size_t smoothed_points_needed(const SurfaceInput& surface, const PrepareReport& report,
                                   int spheres);

// Thins the prepared `surface` (points and normals) to about `budget` points, one per voxel
// (src/core/subsample.hpp), when it has more; the report's stand_in and kept follow.
void thin_smoothed_cloud(SurfaceInput& surface, PrepareReport& report, std::size_t budget);

// Turns the working frame of `report` and the prepared `surface` in it `turn` times by a fixed
// angle about the frame's diagonal: the same points, in coordinates that round differently (and
// another start of the optimisation, Options::starts).
void turn_working_frame(PrepareReport& report, SurfaceInput& surface, int turn);

// Shrinking-ball settings suited to what preparation left. Smoothed (noisy) data: samples that
// scatter around the smoothed surface by the residual noise must not shrink a ball, and a ball
// whose centre is outside the shape is rejected (noise flips normals near thin parts). Data
// with holes: balls reach past its bounding box by twice the residual noise at most (0.1 % of
// the diagonal at least). Clean closed data keeps `options` as they are.
void adapt_shrinking_ball(const PrepareReport& report, ShrinkingBallOptions& options);

}  // namespace vmas
