#include "vmas/projection.hpp"

#include <cmath>
#include <string>

#include "vmas/error.hpp"

namespace vmas {

void ShrinkingBallOptions::validate() const {
  if (max_iterations < 1 || max_iterations > 1000)
    throw InvalidOption("shrinking-ball iterations must be between 1 and 1000 (got " +
                        std::to_string(max_iterations) + ")");
  if (!(tolerance >= 0.0 && tolerance < 0.1))
    throw InvalidOption("shrinking-ball tolerance must be in [0, 0.1) (got " +
                        std::to_string(tolerance) + ")");
  if (!(initial_radius > 0.0 && initial_radius <= 100.0))
    throw InvalidOption("shrinking-ball initial radius must be in (0, 100] (got " +
                        std::to_string(initial_radius) + ")");
  if (!(denoise_angle_deg >= 0.0 && denoise_angle_deg < 180.0))
    throw InvalidOption("denoise angle must be in [0, 180) degrees (got " +
                        std::to_string(denoise_angle_deg) + ")");
}

MedialProjector::MedialProjector(const Shape& shape, const ShrinkingBallOptions& options)
    : shape_(shape),
      options_(options),
      tree_(shape.points),
      cos_denoise_(std::cos(options.denoise_angle_deg * M_PI / 180.0)) {
  options_.validate();
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
  return reverse.radius < ball.radius ? reverse : ball;
}

bool MedialProjector::seen_from_inside(const Sphere& ball, int contact) const {
  return contact >= 0 && shape_.normals[contact].dot(shape_.points[contact] - ball.center) > 0.0;
}

Sphere MedialProjector::shrink_along(int vertex, const Vec3& inward, int& contact) const {
  const Vec3& p = shape_.points[vertex];
  const double delta = options_.tolerance * shape_.diagonal;
  double radius = options_.initial_radius * shape_.diagonal;
  Vec3 center = p + radius * inward;
  contact = -1;
  for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
    double squared_distance = 0.0;
    const int nearest = tree_.nearest(center, &squared_distance);
    if (nearest == vertex || std::sqrt(squared_distance) >= radius - delta) break;
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
