#include "optimise/projection.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "optimise/exterior.hpp"
#include "vmas/error.hpp"

namespace vmas {

namespace {
// Probe balls of the enclosure measure, and those narrower than this many sample spacings,
// which measure no enclosed volume.
constexpr int kEnclosureProbes = 200;
constexpr double kMinProbeRadiusInSpacings = 0.5;
// A block of vertices this many of its radii away from a point counts as one dipole (relative
// error of the winding number ~ 1/kFarInRadii²).
constexpr double kFarInRadii = 3.0;
// A ball whose centre has a smaller winding number lies outside the shape: ~1 inside, ~0
// outside, and ~½ on the inner side of a thin part that smoothing folded onto one sheet.
constexpr double kInside = 0.25;
// Outside balls are rejected on data whose enclosure is at least this: smoothed closed shapes
// with thin parts read well below kEnclosed, single-view scans lower still.
constexpr double kRejectionEnclosure = 0.3;
// The exterior grid's sample spacing, in support radii √A(v) of the points (the mean distance to
// the 6 nearest): about the distance to the sixth nearest.
constexpr double kSpacingInSupportRadii = 1.3;
// Cells of the exterior grids, in sample spacings. The coarser walls have no gap where samples
// are a spacing apart, but also close narrow gaps between parts (an ear against a head) into
// pockets that the fill misses; the finer ones leave those open where the sampling is dense.
constexpr std::array<double, 2> kExteriorCellsInSpacings = {1.0, 0.75};
// A grid is dropped when, at more than this fraction of the enclosure's probe points, the
// empty balls on both sides have their centre outside it: the fill has reached the inside
// through a gap in its walls, a hole or an open side (on closed data one of the two is inside,
// or in the wall of a thin part).
constexpr double kMostProbesOutside = 0.2;
// inside_out(): the offset on each side of a vertex, in its support radii √A(v) (a sample
// spacing is about 1.3 of them), and the difference of the two winding numbers that reads inside out (+1 for a patch
// turned over, −1 for one oriented right). On the smoothed, thinned clouds of the benchmark's
// noisy rows without normals, offsets of 3, 4 and 6 gave the same ε within their spread.
constexpr double kInsideOutOffset = 4.0;
constexpr double kInsideOutJump = 0.5;
// A squared search bound this much past the square of a distance holds every point nearer than
// that distance, whatever the rounding of the square (shrink_along).
constexpr double kSquareSlack = 1.0 + 1e-12;
// Smallest radius of a ball, relative to the diagonal.
constexpr double kMinRadius = 1e-6;
}  // namespace
void ShrinkingBallOptions::validate() const {
  if (max_iterations < 1 || max_iterations > 1000)
    throw InvalidOption("max_iterations", "must be between 1 and 1000 (got " +
                                              std::to_string(max_iterations) + ")");
  if (!(tolerance >= 0.0 && tolerance < 0.1))
    throw InvalidOption("tolerance",
                        "must be in [0, 0.1) (got " + std::to_string(tolerance) + ")");
  if (!(enclosure < 0.0 || std::isfinite(enclosure)))
    throw InvalidOption("enclosure", "must be finite or negative (got " +
                                         std::to_string(enclosure) + ")");
  if (!(box_margin >= 0.0 && box_margin <= 1.0))
    throw InvalidOption("box_margin",
                        "must be in [0, 1] (got " + std::to_string(box_margin) + ")");
  if (!(initial_radius > 0.0 && initial_radius <= 100.0))
    throw InvalidOption("initial_radius",
                        "must be in (0, 100] (got " + std::to_string(initial_radius) + ")");
  if (!(denoise_angle_deg >= 0.0 && denoise_angle_deg < 180.0))
    throw InvalidOption("denoise_angle_deg", "must be in [0, 180) degrees (got " +
                                             std::to_string(denoise_angle_deg) + ")");
}

MedialProjector::MedialProjector(const Shape& shape, const ShrinkingBallOptions& options)
    : MedialProjector(shape, options, true) {}

double MedialProjector::enclosure_of(const Shape& shape, const ShrinkingBallOptions& options) {
  return MedialProjector(shape, options, false).enclosure();
}

std::vector<int> MedialProjector::inside_out(const Shape& shape) {
  const MedialProjector projector(shape, {}, false);
  if (projector.enclosure() < kEnclosed) return {};
  const int count = shape.size();
  std::vector<char> turned(count, 0);
#pragma omp parallel for schedule(dynamic, 256)
  for (int v = 0; v < count; ++v) {
    const Vec3 step = kInsideOutOffset * std::sqrt(shape.area[v]) * shape.normals[v];
    const Vec3& p = shape.points[v];
    turned[v] = projector.winding_number(p + step) - projector.winding_number(p - step) >
                kInsideOutJump;
  }
  std::vector<int> vertices;
  for (int v = 0; v < count; ++v)
    if (turned[v]) vertices.push_back(v);
  return vertices;
}

MedialProjector::MedialProjector(const Shape& shape, const ShrinkingBallOptions& options,
                                 bool with_exteriors)
    : shape_(shape),
      options_(options),
      tree_(shape.points),
      cos_denoise_(std::cos(options.denoise_angle_deg * M_PI / 180.0)) {
  options_.validate();
  const Box box = bounding_box(shape.points);
  const Vec3 margin = Vec3::Constant(options_.box_margin * shape.diagonal);
  box_low_ = box.min() - margin;
  box_high_ = box.max() + margin;
  const VertexBlocks& blocks = shape.blocks;
  dipoles_.resize(blocks.size());
  for (int b = 0; b < blocks.size(); ++b) {
    BlockDipole& block = dipoles_[b];
    block.center = block.moment = Vec3::Zero();
    double area = 0.0;
    for (int k = blocks.offsets[b]; k < blocks.offsets[b + 1]; ++k) {
      const int v = blocks.vertices[k];
      block.center += shape.area[v] * shape.points[v];
      block.moment += shape.area[v] * shape.normals[v];
      area += shape.area[v];
    }
    block.center = area > 0.0 ? Vec3(block.center / area) : blocks.centers[b];
    block.radius = 0.0;
    for (int k = blocks.offsets[b]; k < blocks.offsets[b + 1]; ++k)
      block.radius =
          std::max(block.radius, (shape.points[blocks.vertices[k]] - block.center).norm());
  }
  // Inside and outside mean something only for data that encloses a volume.
  enclosure_ = options_.enclosure >= 0.0 ? options_.enclosure : measure_enclosure();
  // A cloud's normals can be wrong where estimation fails (thin parts, sparse or noisy samples),
  // and so can the winding number built on them; the voxels the samples wall off are not.
  if (with_exteriors && !shape.is_mesh) {
    double spacing = 0.0;
    for (double a : shape.area) spacing += std::sqrt(a);
    spacing *= kSpacingInSupportRadii / std::max(1, shape.size());
    for (double cells : kExteriorCellsInSpacings) {
      auto grid = std::make_unique<internal::ExteriorGrid>(shape.points, cells * spacing);
      if (walls_inside_off(*grid)) exteriors_.push_back(std::move(grid));
    }
  }
  reject_outside_ = options_.reject_outside && enclosure_ >= kRejectionEnclosure;
}

MedialProjector::~MedialProjector() = default;

double MedialProjector::radius_limit(const Vec3& p, const Vec3& inward) const {
  // Per axis, centre ± radius within [low, high]: p + r·d + r ≤ high and p + r·d − r ≥ low.
  double limit = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const double d = inward[axis];
    if (1.0 + d > 0.0) limit = std::min(limit, (box_high_[axis] - p[axis]) / (1.0 + d));
    if (1.0 - d > 0.0) limit = std::min(limit, (p[axis] - box_low_[axis]) / (1.0 - d));
  }
  return std::max(limit, 0.0);
}

double MedialProjector::winding_number(const Vec3& q) const {
  const VertexBlocks& blocks = shape_.blocks;
  double sum = 0.0;
  for (int b = 0; b < blocks.size(); ++b) {
    const BlockDipole& block = dipoles_[b];
    const Vec3 offset = block.center - q;
    const double distance = offset.norm();
    if (distance > kFarInRadii * block.radius) {
      sum += block.moment.dot(offset) / (distance * distance * distance);
      continue;
    }
    for (int k = blocks.offsets[b]; k < blocks.offsets[b + 1]; ++k) {
      const int v = blocks.vertices[k];
      const Vec3 to_vertex = shape_.points[v] - q;
      const double d = to_vertex.norm();
      if (d > 0.0) sum += shape_.area[v] * shape_.normals[v].dot(to_vertex) / (d * d * d);
    }
  }
  return sum / (4.0 * M_PI);
}

bool MedialProjector::walls_inside_off(const internal::ExteriorGrid& grid) const {
  const std::vector<int> probes = enclosure_probes();
  std::size_t leaked = 0;
  int contact = -1;
  for (int vertex : probes) {
    const Vec3& n = shape_.normals[vertex];
    if (grid.outside(shrink_along(vertex, n, contact).center) &&
        grid.outside(shrink_along(vertex, -n, contact).center))
      ++leaked;
  }
  return !probes.empty() && leaked <= kMostProbesOutside * probes.size();
}

std::vector<int> MedialProjector::enclosure_probes() const {
  const int count = shape_.size();
  const int stride = std::max(1, count / kEnclosureProbes);
  std::vector<int> probes;
  for (int vertex = 0; vertex < count; vertex += stride) probes.push_back(vertex);
  return probes;
}

double MedialProjector::measure_enclosure() const {
  const std::vector<int> probes = enclosure_probes();
  std::vector<double> winding(probes.size(), 0.0);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < probes.size(); ++c) {
    const int vertex = probes[c];
    const Sphere ball = ball_at(vertex);
    // Next to the samples the sum of dipoles is no integral any more; a ball no wider than the
    // sample spacing finds no volume either (a flat or single-layer piece), so it counts as 0.
    if (ball.radius > kMinProbeRadiusInSpacings * std::sqrt(shape_.area[vertex]))
      winding[c] = winding_number(ball.center);
  }
  return median(std::move(winding));
}

Sphere MedialProjector::shrink(int vertex, const Vec3& inward) const {
  int contact = -1;
  const Sphere ball = shrink_along(vertex, inward, contact);
  if (seen_from_inside(ball, contact)) return ball;
  // `inward` points out of the shape (a normal flipped by noise): the first ball found nothing,
  // or stopped on a surface that faces its centre (the outside of the shape). Try the other side.
  // If neither side is clearly inside (noise, an open scan), the smaller ball does less harm.
  int reverse_contact = -1;
  const Sphere reverse = shrink_along(vertex, -inward, reverse_contact);
  if (seen_from_inside(reverse, reverse_contact)) return reverse;
  // Both balls are outside a closed shape (normals flipped around a thin part): a ball as small
  // as the tolerance, just inside the surface, is not right either, but it does not stick out.
  if (reject_outside_ || !exteriors_.empty()) {
    const double radius = std::max(options_.tolerance, kMinRadius) * shape_.diagonal;
    return Sphere{shape_.points[vertex] - radius * shape_.normals[vertex], radius};
  }
  return reverse.radius < ball.radius ? reverse : ball;
}

bool MedialProjector::seen_from_inside(const Sphere& ball, int contact) const {
  return contact >= 0 && shape_.normals[contact].dot(shape_.points[contact] - ball.center) > 0.0 &&
         std::none_of(exteriors_.begin(), exteriors_.end(),
                      [&](const auto& grid) { return grid->outside(ball.center); }) &&
         (!reject_outside_ || winding_number(ball.center) > kInside);
}

Sphere MedialProjector::shrink_along(int vertex, const Vec3& inward, int& contact) const {
  const Vec3& p = shape_.points[vertex];
  const double delta = options_.tolerance * shape_.diagonal;
  double radius = std::min(options_.initial_radius * shape_.diagonal, radius_limit(p, inward));
  Vec3 center = p + radius * inward;
  contact = -1;
  for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
    // Only a point well inside the ball shrinks it: the search looks no farther (than a bound
    // a little past `reach`, so that rounding of the square cannot leave out a point that the
    // test below takes). The vertex itself lies on the ball's surface.
    double squared_distance = 0.0;
    const double reach = radius - delta;
    const int nearest =
        reach > 0.0
            ? tree_.nearest_within(center, reach * reach * kSquareSlack, &squared_distance)
            : -1;
    if (nearest < 0 || nearest == vertex || std::sqrt(squared_distance) >= reach) break;
    const Vec3& q = shape_.points[nearest];
    const double along = inward.dot(q - p);
    if (!(along > 0.0)) break;  // q behind the tangent plane: cannot be inside the ball
    const double next_radius = (p - q).squaredNorm() / (2.0 * along);
    const Vec3 next_center = p + next_radius * inward;
    // Two contacts seen from the centre at a tiny angle are noise, not two sides of the shape.
    if (iteration > 0 && cos_denoise_ < 1.0) {
      const Vec3 to_p = (p - next_center).normalized();
      const Vec3 to_q = (q - next_center).normalized();
      if (to_p.dot(to_q) > cos_denoise_) break;
    }
    radius = next_radius;
    center = next_center;
    contact = nearest;
  }
  return Sphere{center, radius};
}

Sphere MedialProjector::project(const Vec3& center) const {
  const int closest = tree_.nearest(center);
  const Vec3& normal = shape_.normals[closest];
  Vec3 direction = center - shape_.points[closest];
  const double length = direction.norm();
  if (length > 0.0 && direction.dot(normal) < 0.0)
    direction /= length;
  else
    direction = -normal;
  return shrink(closest, direction);
}

}  // namespace vmas
