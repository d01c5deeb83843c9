// Density fields: checking one given per point, and making one by a rule (vmas/vmas.hpp).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/kdtree.hpp"
#include "core/principal_axes.hpp"
#include "vmas/error.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

// The curvature rule: neighbours of a point's plane fit, the density at the most curved points,
// and the share of points that reach it.
constexpr int kCurvatureNeighbours = 16;
constexpr double kMostCurvedDensity = 4.0;
constexpr double kMostCurvedShare = 0.05;
// The distance rule's density within its radius, unless given.
constexpr double kNearDensity = 4.0;
// The rules' names.
const std::string kCurvatureRule = "curvature", kDistanceRule = "distance-to:";

std::string figure(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::vector<double> curvature_density(const std::vector<Vec3>& points) {
  std::vector<int> finite;
  std::vector<Vec3> usable;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i].allFinite()) {
      finite.push_back(static_cast<int>(i));
      usable.push_back(points[i]);
    }
  std::vector<double> density(points.size(), 1.0);
  if (usable.size() < 3) return density;
  const KdTree tree(usable);
  std::vector<double> variation(usable.size(), 0.0);
#pragma omp parallel
  {
    std::vector<int> neighbours;
    std::vector<double> squared;
#pragma omp for schedule(static)
    for (int i = 0; i < static_cast<int>(usable.size()); ++i) {
      tree.k_nearest(usable[i], kCurvatureNeighbours, neighbours, squared);
      const internal::PrincipalAxes axes = internal::principal_axes(usable, neighbours);
      const double spread = axes.spread.sum();
      if (axes.valid && spread > 0.0) variation[i] = std::max(0.0, axes.spread[0]) / spread;
    }
  }
  std::vector<double> sorted = variation;
  const auto at =
      sorted.begin() + static_cast<std::ptrdiff_t>((1.0 - kMostCurvedShare) *
                                                   static_cast<double>(sorted.size() - 1));
  std::nth_element(sorted.begin(), at, sorted.end());
  const double most_curved = *at;
  if (!(most_curved > 0.0)) return density;  // flat (or nearly) everywhere
  for (std::size_t i = 0; i < usable.size(); ++i)
    density[finite[i]] =
        1.0 + (kMostCurvedDensity - 1.0) * std::min(1.0, variation[i] / most_curved);
  return density;
}

// "X,Y,Z,R[,D]" after "distance-to:".
std::vector<double> distance_density(const std::vector<Vec3>& points, const std::string& rule,
                                     const std::string& arguments) {
  std::vector<double> values;
  std::size_t start = 0;
  while (start <= arguments.size()) {
    const std::size_t end = std::min(arguments.find(',', start), arguments.size());
    double value = 0.0;
    const char* first = arguments.data() + start;
    const char* last = arguments.data() + end;
    const auto [stop, error] = std::from_chars(first, last, value);
    if (error != std::errc() || stop != last || !std::isfinite(value))
      throw InvalidOption("density", "'" + rule + "': '" + std::string(first, last) +
                                         "' is not a number (expected distance-to:X,Y,Z,R[,D])");
    values.push_back(value);
    start = end + 1;
  }
  if (values.size() != 4 && values.size() != 5)
    throw InvalidOption("density", "'" + rule + "': expected distance-to:X,Y,Z,R[,D] (" +
                                       std::to_string(values.size()) + " numbers given)");
  if (!(values[3] > 0.0))
    throw InvalidOption("density", "'" + rule + "': the radius R must be positive");
  const double near = values.size() == 5 ? values[4] : kNearDensity;
  if (!(near >= 0.0))
    throw InvalidOption("density", "'" + rule + "': the density D must be 0 or more");
  const Vec3 centre(values[0], values[1], values[2]);
  std::vector<double> density(points.size(), 1.0);
  for (std::size_t i = 0; i < points.size(); ++i)
    if ((points[i] - centre).norm() <= values[3]) density[i] = near;
  return density;
}

}  // namespace

void check_density(const std::vector<double>& density, std::size_t points) {
  if (density.size() != points)
    throw InvalidInput("the density has " + std::to_string(density.size()) + " values for " +
                       std::to_string(points) + " points");
  bool any_positive = false;
  for (std::size_t i = 0; i < density.size(); ++i) {
    const double value = density[i];
    if (std::isnan(value))
      throw InvalidInput("the density of point " + std::to_string(i) + " is not a number");
    if (!std::isfinite(value))
      throw InvalidInput("the density of point " + std::to_string(i) + " is infinite");
    if (value < 0.0)
      throw InvalidInput("the density of point " + std::to_string(i) + " is negative (" +
                         figure(value) + ")");
    any_positive = any_positive || value > 0.0;
  }
  if (!any_positive && !density.empty())
    throw InvalidInput("every density value is 0: some point must have a positive density");
}

bool is_density_rule(const std::string& text) {
  return text == kCurvatureRule || text.compare(0, kDistanceRule.size(), kDistanceRule) == 0;
}

std::vector<double> density_by_rule(const SurfaceInput& surface, const std::string& rule) {
  if (rule == kCurvatureRule) return curvature_density(surface.points);
  if (is_density_rule(rule))
    return distance_density(surface.points, rule, rule.substr(kDistanceRule.size()));
  throw InvalidOption("density",
                      "'" + rule + "' is no density rule (curvature, distance-to:X,Y,Z,R[,D])");
}

}  // namespace vmas
