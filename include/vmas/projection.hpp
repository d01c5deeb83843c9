#pragma once
// Projection onto the medial axis (paper §3.3, "Sphere projection") by the shrinking-ball
// algorithm (Ma, Bae, Choi 2012) over an exact KD-tree of the input points, with the
// separation-angle denoising of Peters & Ledoux (2016).
#include "vmas/kdtree.hpp"
#include "vmas/shape.hpp"

namespace vmas {

struct ShrinkingBallOptions {
  int max_iterations = 30;
  double tolerance = 1e-5;          // δ, relative to the bounding-box diagonal
  double initial_radius = 1.0;      // first ball radius, relative to the diagonal
  double denoise_angle_deg = 20.0;  // stop shrinking when the two contacts separate by less
                                    // than this (noise, not a medial feature); 0 disables it
  void validate() const;            // throws InvalidOption
};

class MedialProjector {
 public:
  MedialProjector(const Shape& shape, const ShrinkingBallOptions& options);

  // The largest empty ball touching `vertex` whose centre lies along the unit `inward` direction
  // (or along −inward when that side is the outside: a flipped normal).
  Sphere shrink(int vertex, const Vec3& inward) const;

  // The medial ball touching `vertex` along its inward normal: how new spheres are seeded.
  Sphere ball_at(int vertex) const { return shrink(vertex, -shape_.normals[vertex]); }

  // Moves a fitted sphere centre onto the medial axis: the shrinking ball from the input point
  // closest to `center`, in the direction of `center` if that points inside, else along −normal.
  Sphere project(const Vec3& center) const;

 private:
  // One shrinking-ball run; `contact` is the sample that last shrank the ball (-1: none).
  Sphere shrink_along(int vertex, const Vec3& inward, int& contact) const;
  // Whether the ball lies inside the surface at its contact (the contact's normal points away
  // from the centre), as a medial ball must.
  bool seen_from_inside(const Sphere& ball, int contact) const;

  const Shape& shape_;
  ShrinkingBallOptions options_;
  KdTree tree_;
  double cos_denoise_;
};

}  // namespace vmas
