#pragma once
// Projection onto the medial axis (paper §3.3, "Sphere projection") by the shrinking-ball
// algorithm (Ma, Bae, Choi 2012) over an exact KD-tree of the input points, with the
// separation-angle denoising of Peters & Ledoux (2016).
#include <memory>
#include <vector>

#include "core/kdtree.hpp"
#include "vmas/options.hpp"
#include "vmas/skeletonizer.hpp"

namespace vmas {

namespace internal {
class ExteriorGrid;
}

class MedialProjector {
 public:
  MedialProjector(const Shape& shape, const ShrinkingBallOptions& options);
  ~MedialProjector();

  // The largest empty ball touching `vertex` whose centre lies along the unit `inward` direction
  // (or along −inward when that side is the outside: a flipped normal).
  Sphere shrink(int vertex, const Vec3& inward) const;

  // The medial ball touching `vertex` along its inward normal: how new spheres are seeded.
  Sphere ball_at(int vertex) const { return shrink(vertex, -shape_.normals[vertex]); }

  // The input point closest to `p`.
  int nearest_vertex(const Vec3& p) const { return tree_.nearest(p); }

  // Moves a fitted sphere centre onto the medial axis: the shrinking ball from the input point
  // closest to `center`, in the direction of `center` if that points inside, else along −normal.
  Sphere project(const Vec3& center) const;

  // How well the data encloses a volume: the median generalized winding number at the centres
  // of the medial balls of evenly spread vertices (measured once, at construction). About 1 for a
  // closed, consistently oriented surface; around 0.5 or less for a single-view scan, an open
  // mesh or one whose faces disagree in orientation. When the options ask for it and the data is
  // not far from enclosed, balls whose centre has a winding number below ¼ lie outside and are
  // rejected.
  double enclosure() const { return enclosure_; }
  static constexpr double kEnclosed = 0.8;
  // enclosure() of a projector on `shape`, without building what only its balls need (a cloud's
  // exterior grids): for a figure judged on a denser sampling (ShrinkingBallOptions::enclosure).
  static double enclosure_of(const Shape& shape, const ShrinkingBallOptions& options);

  // The vertices of `shape` whose normal reads inside out: the winding number a few sample
  // spacings out along it is clearly higher than as far in against it. Seen from that far, a
  // patch narrower than the offset weighs little, and the rest of a surface oriented right reads
  // 1 inside and 0 outside: a small patch turned over is found (a wider one reads right, its own
  // samples ±½ outweighing the rest). A part thinner than the offset reads the same on both
  // sides and is left alone. None when `shape` does not enclose a volume (its own enclosure()
  // below kEnclosed, measured on these points: on a thinned cloud it reads lower next to thin
  // parts than on all its points): the rest of an open surface reads no 1 inside. Ascending.
  static std::vector<int> inside_out(const Shape& shape);

  // Generalized winding number at `q` (Barill et al. 2018) from the vertices' areas and normals:
  // blocks of vertices far from `q` count as one dipole. ~1 inside a closed surface, ~0 outside.
  double winding_number(const Vec3& q) const;

 private:
  // One shrinking-ball run; `contact` is the sample that last shrank the ball (-1: none).
  Sphere shrink_along(int vertex, const Vec3& inward, int& contact) const;
  // Whether the ball lies inside the surface at its contact (the contact's normal points away
  // from the centre), as a medial ball must, and (clouds) its centre is not in the exterior grid.
  bool seen_from_inside(const Sphere& ball, int contact) const;

  // The largest radius of a ball touching `p` with its centre along `inward` that stays inside
  // the data's bounding box (plus a margin): a ball that finds no sample must not grow past the
  // data (open scans), and a medial ball of a closed shape never needs to.
  double radius_limit(const Vec3& p, const Vec3& inward) const;

  MedialProjector(const Shape& shape, const ShrinkingBallOptions& options, bool with_exteriors);
  double measure_enclosure() const;
  std::vector<int> enclosure_probes() const;  // evenly spread vertices
  // Whether `grid` walls the inside off (no gap lets its fill in).
  bool walls_inside_off(const internal::ExteriorGrid& grid) const;

  struct BlockDipole {  // the vertices of one of shape.blocks seen from afar
    Vec3 center;        // area-weighted
    Vec3 moment;        // Σ A(v) n_v
    double radius;      // of the block around `center`
  };

  const Shape& shape_;
  ShrinkingBallOptions options_;
  KdTree tree_;
  double cos_denoise_;
  Vec3 box_low_, box_high_;  // bounding box grown by the margin
  std::vector<BlockDipole> dipoles_;
  bool reject_outside_ = false;  // balls with an outside centre are rejected
  // Clouds: the voxels outside the samples, at the cell sizes whose walls shut the inside off
  // (src/optimise/exterior.hpp).
  std::vector<std::unique_ptr<internal::ExteriorGrid>> exteriors_;
  double enclosure_ = 0.0;
};

}  // namespace vmas
