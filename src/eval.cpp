#include "vmas/eval.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "vmas/error.hpp"
#include "vmas/kdtree.hpp"

namespace vmas {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
// Boundary samples of one measurement at most (a few hundred bytes each while measured).
constexpr double kMaxBoundarySamples = 5e5;

Box sphere_box(const Vec3& center, double radius) {
  const Vec3 extent = Vec3::Constant(radius);
  return Box(center - extent, center + extent);
}

double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// The convex hull of two spheres. When one contains the other it is the bigger sphere, stored in
// c1/r1 with `is_sphere` set.
struct Cone {
  Vec3 c1, c2, axis;
  double r1 = 0.0, r2 = 0.0, h = 0.0;
  double a = 1.0, b = 0.0;  // (cos, sin) of the lateral surface's slope against the axis
  bool is_sphere = false;

  Cone(const Sphere& s1, const Sphere& s2)
      : c1(s1.center), c2(s2.center), r1(s1.radius), r2(s2.radius), h((c2 - c1).norm()) {
    if (h <= std::abs(r1 - r2)) {
      is_sphere = true;
      if (r2 > r1) {
        c1 = c2;
        r1 = r2;
      }
      return;
    }
    axis = (c2 - c1) / h;
    b = (r1 - r2) / h;
    a = std::sqrt(1.0 - b * b);
  }

  // In the (axial x, radial y) half-plane the boundary is circle 1, the tangent segment and
  // circle 2; the normal of the segment is (b, a), which splits the plane into three regions.
  double signed_distance(const Vec3& p) const {
    const Vec3 q = p - c1;
    if (is_sphere) return q.norm() - r1;
    const double x = q.dot(axis);
    const double y = (q - x * axis).norm();
    const double k = a * x - b * y;
    if (k < 0.0) return q.norm() - r1;
    if (k > a * h) return (p - c2).norm() - r2;
    return a * y + b * x - r1;
  }

  Box box() const {
    Box box = sphere_box(c1, r1);
    if (!is_sphere) box.extend(sphere_box(c2, r2));
    return box;
  }
};

// The convex hull of three spheres, i.e. the union of the spheres interpolated linearly over the
// triangle. Distance to it = min over the triangle of |p - c(t)| - r(t), a convex function of t:
// its minimum is either the interior critical point, where it equals the distance to a tangent
// plane, or on an edge, where it is the cone's distance.
struct Slab {
  std::array<Cone, 3> cones;
  bool has_planes = false;
  Vec3 c0, e1, e2, normal, gradient;  // gradient: of the radius, interpolated over the plane
  double r0 = 0.0, s = 0.0;           // s = sqrt(1 - |gradient|^2)
  double d00 = 0.0, d01 = 0.0, d11 = 0.0, det = 0.0;
  std::array<std::array<Vec3, 3>, 2> triangles;

  Slab(const Sphere& s0, const Sphere& s1, const Sphere& s2)
      : cones{Cone(s0, s1), Cone(s1, s2), Cone(s2, s0)},
        c0(s0.center),
        e1(s1.center - s0.center),
        e2(s2.center - s0.center),
        r0(s0.radius) {
    d00 = e1.squaredNorm();
    d01 = e1.dot(e2);
    d11 = e2.squaredNorm();
    const Vec3 cross = e1.cross(e2);
    det = cross.squaredNorm();  // = d00 * d11 - d01^2, without the cancellation
    // (Nearly) collinear centres: the minimum is on an edge.
    if (!(det > 1e-12 * d00 * d11)) return;
    const double dr1 = s1.radius - r0, dr2 = s2.radius - r0;
    gradient = ((d11 * dr1 - d01 * dr2) * e1 + (d00 * dr2 - d01 * dr1) * e2) / det;
    const double g2 = gradient.squaredNorm();
    // |gradient| >= 1: one sphere is inside (or internally tangent to) another, no tangent plane.
    if (g2 >= 1.0) return;
    has_planes = true;
    s = std::sqrt(1.0 - g2);
    normal = cross.normalized();
    const std::array<const Sphere*, 3> spheres{&s0, &s1, &s2};
    for (int i = 0; i < 3; ++i) {
      const Sphere& sphere = *spheres[i];
      triangles[0][i] = sphere.center + sphere.radius * (s * normal - gradient);
      triangles[1][i] = sphere.center + sphere.radius * (-s * normal - gradient);
    }
  }

  double signed_distance(const Vec3& p) const {
    if (has_planes) {
      const double height = (p - c0).dot(normal);
      const Vec3 in_plane = p - height * normal;
      const Vec3 v = in_plane + gradient * (std::abs(height) / s) - c0;
      const double d20 = v.dot(e1), d21 = v.dot(e2);
      const double u = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
      if (u >= 0.0 && w >= 0.0 && u + w <= 1.0) {
        return s * std::abs(height) - (r0 + gradient.dot(in_plane - c0));
      }
    }
    return std::min(
        {cones[0].signed_distance(p), cones[1].signed_distance(p), cones[2].signed_distance(p)});
  }

  Box box() const { return cones[0].box().extend(cones[1].box()).extend(cones[2].box()); }
};

// Bounding-volume hierarchy over boxes (median split on the longest axis). The queries take the
// exact per-item test as a callback, so one tree type serves primitives and input triangles.
class Bvh {
 public:
  explicit Bvh(const std::vector<Box>& boxes) : boxes_(boxes), items_(boxes.size()) {
    for (std::size_t i = 0; i < items_.size(); ++i) items_[i] = static_cast<int>(i);
    if (!items_.empty()) build(0, static_cast<int>(items_.size()));
  }

  // Smallest distance(item) over all items; distance(item) must be at least the distance from p
  // to the item's box, which is what prunes the search. Returns early, with some distance below
  // `stop_below`, once one is found (for callers that only need the values above it).
  // `hint`: an item likely to be near, tried first (a tight bound prunes sooner); set to the
  // nearest item found.
  template <class Distance>
  double nearest(const Vec3& p, Distance&& distance, double stop_below = -kInfinity,
                 int* hint = nullptr) const {
    double best = kInfinity;
    if (nodes_.empty()) return best;
    if (hint && *hint >= 0) best = distance(*hint);
    if (best < stop_below) return best;
    int stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (node.box.squaredExteriorDistance(p) >= best * best) continue;
      if (node.count > 0) {
        for (int i = node.first; i < node.first + node.count; ++i) {
          const double d = distance(items_[i]);
          if (d >= best) continue;
          best = d;
          if (hint) *hint = items_[i];
        }
        if (best < stop_below) return best;
        continue;
      }
      const int left = node.first, right = node.first + 1;
      const bool left_first = nodes_[left].box.squaredExteriorDistance(p) <
                              nodes_[right].box.squaredExteriorDistance(p);
      stack[top++] = left_first ? right : left;
      stack[top++] = left_first ? left : right;
    }
    return best;
  }

  // Whether accept(item) holds for some item whose box contains p.
  template <class Accept>
  bool any_containing(const Vec3& p, Accept&& accept) const {
    if (nodes_.empty()) return false;
    int stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!node.box.contains(p)) continue;
      if (node.count > 0) {
        for (int i = node.first; i < node.first + node.count; ++i) {
          if (accept(items_[i])) return true;
        }
        continue;
      }
      stack[top++] = node.first;
      stack[top++] = node.first + 1;
    }
    return false;
  }

 private:
  // Inner nodes: children at first and first + 1. Leaves: items_[first, first + count).
  struct Node {
    Box box;
    int first = 0;
    int count = 0;
  };
  static constexpr int kLeafSize = 4;
  static constexpr int kMaxDepth = 128;  // median splits: depth <= log2(n) + 1, two slots per level

  void build(int begin, int end) {
    nodes_.push_back({});
    build_node(static_cast<int>(nodes_.size()) - 1, begin, end);
  }

  void build_node(int index, int begin, int end) {
    Box box, centers;
    for (int i = begin; i < end; ++i) {
      box.extend(boxes_[items_[i]]);
      centers.extend(boxes_[items_[i]].center());
    }
    nodes_[index].box = box;
    if (end - begin <= kLeafSize) {
      nodes_[index].first = begin;
      nodes_[index].count = end - begin;
      return;
    }
    int axis = 0;
    centers.sizes().maxCoeff(&axis);
    const int middle = (begin + end) / 2;
    std::nth_element(
        items_.begin() + begin, items_.begin() + middle, items_.begin() + end,
        [&](int i, int j) { return boxes_[i].center()[axis] < boxes_[j].center()[axis]; });
    const int children = static_cast<int>(nodes_.size());
    nodes_[index].first = children;
    nodes_.resize(nodes_.size() + 2);
    build_node(children, begin, middle);
    build_node(children + 1, middle, end);
  }

  const std::vector<Box>& boxes_;
  std::vector<int> items_;
  std::vector<Node> nodes_;
};

void check_medial(const MedialMesh& medial) {
  if (medial.spheres.empty()) throw InvalidInput("medial mesh has no sphere");
  const int n = static_cast<int>(medial.spheres.size());
  for (int i = 0; i < n; ++i) {
    const Sphere& s = medial.spheres[i];
    if (!s.center.allFinite() || !std::isfinite(s.radius) || s.radius < 0.0) {
      throw InvalidInput("medial sphere " + std::to_string(i) +
                         " has a non-finite coordinate or an invalid radius");
    }
  }
  auto check = [n](const int* indices, int size, const char* what, std::size_t element) {
    for (int k = 0; k < size; ++k) {
      const bool repeated = std::find(indices, indices + k, indices[k]) != indices + k;
      if (indices[k] < 0 || indices[k] >= n || repeated) {
        throw InvalidInput(std::string("medial ") + what + " " + std::to_string(element) +
                           ": sphere index " + std::to_string(indices[k]) +
                           (repeated ? " repeated" : " out of range"));
      }
    }
  };
  for (std::size_t e = 0; e < medial.edges.size(); ++e) check(medial.edges[e].data(), 2, "edge", e);
  for (std::size_t f = 0; f < medial.faces.size(); ++f) check(medial.faces[f].data(), 3, "face", f);
}

// Points on the boundaries of the primitives, with the boundary piece of each: sphere i, then
// cone j (after the spheres), then tangent triangle k (after the cones).
struct BoundarySamples {
  std::vector<Vec3> points;
  std::vector<int> pieces;
};

// The reconstruction: its primitives as solids (for "is this point hidden") and the pieces of
// their boundaries (for "how far is this point from a boundary"). Solid ids: spheres, then cones
// (all edges, face edges included, deduplicated), then slabs.
class Envelope {
 public:
  explicit Envelope(const MedialMesh& medial) : spheres_(medial.spheres) {
    check_medial(medial);
    std::vector<std::array<int, 2>> edges = medial.edges;
    for (const auto& f : medial.faces) {
      edges.push_back({f[0], f[1]});
      edges.push_back({f[1], f[2]});
      edges.push_back({f[2], f[0]});
    }
    for (auto& e : edges) {
      if (e[0] > e[1]) std::swap(e[0], e[1]);
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (const auto& e : edges) cones_.emplace_back(spheres_[e[0]], spheres_[e[1]]);
    // A face given twice adds nothing to the union but would be a solid that every sample near
    // it is tested against once more: kept once, in the order given.
    std::vector<std::array<int, 3>> faces;
    std::set<std::array<int, 3>> seen;
    for (const auto& f : medial.faces) {
      std::array<int, 3> sorted = {f[0], f[1], f[2]};
      std::sort(sorted.begin(), sorted.end());
      if (seen.insert(sorted).second) faces.push_back({f[0], f[1], f[2]});
    }
    for (const auto& f : faces) slabs_.emplace_back(spheres_[f[0]], spheres_[f[1]], spheres_[f[2]]);
    std::vector<std::uint64_t> sphere_keys;
    for (const Sphere& sphere : spheres_) sphere_keys.push_back(key_of(sphere));
    solid_keys_ = sphere_keys;
    for (const auto& e : edges)
      solid_keys_.push_back(key_of(1, {sphere_keys[e[0]], sphere_keys[e[1]]}));
    for (const auto& f : faces)
      solid_keys_.push_back(key_of(2, {sphere_keys[f[0]], sphere_keys[f[1]], sphere_keys[f[2]]}));

    for (const Sphere& s : spheres_) solid_boxes_.push_back(sphere_box(s.center, s.radius));
    for (const Cone& c : cones_) solid_boxes_.push_back(c.box());
    for (const Slab& s : slabs_) solid_boxes_.push_back(s.box());
    piece_keys_.assign(solid_keys_.begin(), solid_keys_.begin() + spheres_.size() + cones_.size());
    const std::size_t first_slab = spheres_.size() + cones_.size();
    for (int i = 0; i < static_cast<int>(slabs_.size()); ++i) {
      if (!slabs_[i].has_planes) continue;
      for (std::uint64_t side = 0; side < slabs_[i].triangles.size(); ++side) {
        triangles_.push_back(slabs_[i].triangles[side]);
        triangle_slab_.push_back(i);
        piece_keys_.push_back(key_of(3, {solid_keys_[first_slab + i], side}));
      }
    }
    // Boundary pieces: sphere surfaces, cone surfaces, tangent triangles.
    piece_boxes_.assign(solid_boxes_.begin(),
                        solid_boxes_.begin() + spheres_.size() + cones_.size());
    for (const auto& t : triangles_) {
      piece_boxes_.push_back(Box(t[0]).extend(t[1]).extend(t[2]));
    }
    solid_tree_.emplace(solid_boxes_);
    piece_tree_.emplace(piece_boxes_);
  }
  Envelope(const Envelope&) = delete;  // the trees refer to the box vectors
  Envelope& operator=(const Envelope&) = delete;

  // Smallest unsigned distance from p to the boundary of any sphere, cone or tangent triangle.
  double boundary_distance(const Vec3& p) const {
    int piece;
    return nearest_piece(p, piece);
  }

  int solid_count() const { return static_cast<int>(solid_keys_.size()); }
  int piece_count() const { return static_cast<int>(piece_keys_.size()); }
  // The same primitive in two envelopes has the same key, whatever its index: a hash of the exact
  // geometry of its spheres (never kUnknown or kNone).
  std::uint64_t solid_key(int solid) const { return solid_keys_[solid]; }
  std::uint64_t piece_key(int piece) const { return piece_keys_[piece]; }
  const Box& solid_box(int solid) const { return solid_boxes_[solid]; }
  const Box& piece_box(int piece) const { return piece_boxes_[piece]; }

  // Unsigned distance from p to the boundary piece.
  double piece_distance(int piece, const Vec3& p) const {
    const int spheres = static_cast<int>(spheres_.size());
    const int cones = static_cast<int>(cones_.size());
    if (piece < spheres)
      return std::abs((p - spheres_[piece].center).norm() - spheres_[piece].radius);
    if (piece < spheres + cones) return std::abs(cones_[piece - spheres].signed_distance(p));
    const auto& t = triangles_[piece - spheres - cones];
    return point_triangle_distance(p, t[0], t[1], t[2]);
  }

  // The nearest piece to p and its distance.
  double nearest_piece(const Vec3& p, int& piece) const {
    piece = -1;
    return piece_tree_->nearest(
        p, [&](int id) { return piece_distance(id, p); }, -kInfinity, &piece);
  }

  // Whether p lies deeper than `tolerance` inside `solid`.
  bool deep_inside(int solid, const Vec3& p, double tolerance) const {
    return solid_signed_distance(solid, p) < -tolerance;
  }

  // A solid other than the owner of `piece` that p lies deeper than `tolerance` inside; -1 when
  // none does. `likely`: a solid to try first (neighbouring samples are mostly hidden by the same
  // one).
  int hider(const Vec3& p, int piece, double tolerance, int likely = -1) const {
    const int owner = owner_solid(piece);
    const auto hides = [&](int id) { return id != owner && deep_inside(id, p, tolerance); };
    if (likely >= 0 && hides(likely)) return likely;
    int found = -1;
    solid_tree_->any_containing(p, [&](int id) {
      if (!hides(id)) return false;
      found = id;
      return true;
    });
    return found;
  }

  int owner_solid(int piece) const {
    const int first_triangle = static_cast<int>(spheres_.size() + cones_.size());
    return piece < first_triangle ? piece : first_triangle + triangle_slab_[piece - first_triangle];
  }

  // Samples `spacing` apart on one boundary piece.
  void sample_piece(int piece, double spacing, BoundarySamples& out) const {
    const int spheres = static_cast<int>(spheres_.size());
    const int cones = static_cast<int>(cones_.size());
    if (piece < spheres)
      sample_sphere(spheres_[piece], spacing, piece, out);
    else if (piece < spheres + cones)
      sample_cone(cones_[piece - spheres], spacing, piece, out);
    else
      sample_triangle(triangles_[piece - spheres - cones], spacing, piece, out);
  }

  // How many samples sample_piece would give over all pieces at `spacing` (an upper bound for
  // cones), counted in floating point: a sphere far larger than the shape must not overflow it.
  double sample_count(double spacing) const {
    double count = 0.0;
    for (const Sphere& s : spheres_)
      count += std::max(4.0, std::ceil(4.0 * kPi * s.radius * s.radius / (spacing * spacing)));
    for (const Cone& c : cones_) {
      if (c.is_sphere) continue;
      const double slant = std::hypot(c.h + (c.r2 - c.r1) * c.b, (c.r1 - c.r2) * c.a);
      const double rings = std::max(2.0, std::ceil(slant / spacing) + 1.0);
      count += rings * std::max(3.0, std::ceil(2.0 * kPi * std::max(c.r1, c.r2) * c.a / spacing));
    }
    for (const auto& t : triangles_) {
      const double longest =
          std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
      const double n = std::max(1.0, std::ceil(longest / spacing));
      count += (n + 1.0) * (n + 2.0) / 2.0;
    }
    return count;
  }

  // Samples `spacing` apart on every boundary piece (sphere, cone lateral surface, tangent
  // triangle), with the piece each lies on; hidden ones included.
  BoundarySamples sample_boundaries(double spacing) const {
    BoundarySamples samples;
    for (int piece = 0; piece < piece_count(); ++piece) sample_piece(piece, spacing, samples);
    return samples;
  }

  // The samples that are not deeper than `tolerance` inside a primitive other than their own.
  BoundarySamples visible(const BoundarySamples& samples, double tolerance) const {
    const auto count = static_cast<std::ptrdiff_t>(samples.points.size());
    std::vector<char> keep(samples.points.size());
#pragma omp parallel
    {
      int last_hider = -1;
#pragma omp for schedule(dynamic, 4096)
      for (std::ptrdiff_t i = 0; i < count; ++i) {
        const int hider_found = hider(samples.points[i], samples.pieces[i], tolerance, last_hider);
        keep[i] = hider_found < 0;
        if (hider_found >= 0) last_hider = hider_found;
      }
    }
    BoundarySamples result;
    for (std::size_t i = 0; i < samples.points.size(); ++i) {
      if (!keep[i]) continue;
      result.points.push_back(samples.points[i]);
      result.pieces.push_back(samples.pieces[i]);
    }
    return result;
  }

  // A grid of points `step` apart within `radius` of the sample p on the same piece (tangent
  // plane offsets projected back onto the piece), to refine the maximum around p.
  void sample_around(const Vec3& p, int piece, double radius, double step,
                     BoundarySamples& out) const {
    const int spheres = static_cast<int>(spheres_.size());
    const int cones = static_cast<int>(cones_.size());
    Vec3 normal;
    if (piece < spheres) {
      normal = (p - spheres_[piece].center).normalized();
    } else if (piece < spheres + cones) {
      const Cone& c = cones_[piece - spheres];
      const Vec3 q = p - c.c1;
      normal = c.b * c.axis + c.a * (q - q.dot(c.axis) * c.axis).normalized();
    } else {
      const auto& t = triangles_[piece - spheres - cones];
      normal = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
    }
    // A sphere of radius 0 is a point, its one sample exact: nothing around it to refine (and
    // no tangent plane, whose NaN points would each be measured against every triangle).
    if (!(normal.squaredNorm() > 0.5)) return;
    const Vec3 u = normal.unitOrthogonal(), v = normal.cross(u);
    const int n = static_cast<int>(std::ceil(radius / step));
    for (int i = -n; i <= n; ++i) {
      for (int j = -n; j <= n; ++j) {
        const Vec3 q = p + step * (i * u + j * v);
        Vec3 projected;
        if (!project_onto_piece(q, piece, projected)) continue;
        out.points.push_back(projected);
        out.pieces.push_back(piece);
      }
    }
  }

 private:
  static std::uint64_t key_of(const Sphere& s) {
    return key_of(0, {bits(s.center.x()), bits(s.center.y()), bits(s.center.z()), bits(s.radius)});
  }
  // Order-free for the spheres of a cone or slab; `kind` keeps kinds apart.
  static std::uint64_t key_of(std::uint64_t kind, std::vector<std::uint64_t> parts) {
    if (kind == 1 || kind == 2) std::sort(parts.begin(), parts.end());
    std::uint64_t h = mix(kind + 0x9e3779b97f4a7c15ULL);
    for (std::uint64_t part : parts) h = mix(h ^ part);
    return std::clamp<std::uint64_t>(h, 2, std::numeric_limits<std::uint64_t>::max() - 1);
  }
  static std::uint64_t bits(double x) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
  }
  static std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  }

  // Closest point of the piece to q (q near it); false when q falls outside a triangle.
  bool project_onto_piece(const Vec3& q, int piece, Vec3& projected) const {
    const int spheres = static_cast<int>(spheres_.size());
    const int cones = static_cast<int>(cones_.size());
    if (piece < spheres) {
      const Sphere& s = spheres_[piece];
      projected = s.center + s.radius * (q - s.center).normalized();
      return true;
    }
    if (piece < spheres + cones) {
      // In the (axial, radial) half-plane the lateral surface is a segment.
      const Cone& c = cones_[piece - spheres];
      const Vec3 d = q - c.c1;
      const double x = d.dot(c.axis);
      const Vec3 radial = (d - x * c.axis).normalized();
      const Eigen::Vector2d a(c.r1 * c.b, c.r1 * c.a), b(c.h + c.r2 * c.b, c.r2 * c.a);
      const Eigen::Vector2d ab = b - a;
      const double t = std::clamp(
          (Eigen::Vector2d(x, (d - x * c.axis).norm()) - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const Eigen::Vector2d on = a + t * ab;
      projected = c.c1 + on.x() * c.axis + on.y() * radial;
      return true;
    }
    const auto& t = triangles_[piece - spheres - cones];
    const Vec3 e1 = t[1] - t[0], e2 = t[2] - t[0], v = q - t[0];
    const double d00 = e1.dot(e1), d01 = e1.dot(e2), d11 = e2.dot(e2);
    const double d20 = v.dot(e1), d21 = v.dot(e2), det = d00 * d11 - d01 * d01;
    const double b1 = (d11 * d20 - d01 * d21) / det, b2 = (d00 * d21 - d01 * d20) / det;
    projected = t[0] + b1 * e1 + b2 * e2;
    return b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0;
  }

  double solid_signed_distance(int id, const Vec3& p) const {
    const int spheres = static_cast<int>(spheres_.size());
    const int cones = static_cast<int>(cones_.size());
    if (id < spheres) return (p - spheres_[id].center).norm() - spheres_[id].radius;
    if (id < spheres + cones) return cones_[id - spheres].signed_distance(p);
    return slabs_[id - spheres - cones].signed_distance(p);
  }

  // Fibonacci lattice: near-uniform points, about one per spacing^2 of area.
  static void sample_sphere(const Sphere& s, double spacing, int piece, BoundarySamples& out) {
    const double area = 4.0 * kPi * s.radius * s.radius;
    const int n = std::max(4, static_cast<int>(std::ceil(area / (spacing * spacing))));
    const double golden_angle = kPi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
      const double z = 1.0 - (2.0 * i + 1.0) / n;
      const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
      const double phi = golden_angle * i;
      out.points.push_back(s.center + s.radius * Vec3(rho * std::cos(phi), rho * std::sin(phi), z));
      out.pieces.push_back(piece);
    }
  }

  // Rings between the two circles where the lateral surface touches the spheres.
  static void sample_cone(const Cone& c, double spacing, int piece, BoundarySamples& out) {
    if (c.is_sphere) return;
    const double start = c.r1 * c.b, end = c.h + c.r2 * c.b;
    const double rho1 = c.r1 * c.a, rho2 = c.r2 * c.a;
    const double slant = std::hypot(end - start, rho1 - rho2);
    const int rings = std::max(2, static_cast<int>(std::ceil(slant / spacing)) + 1);
    const Vec3 u = c.axis.unitOrthogonal(), v = c.axis.cross(u);
    for (int j = 0; j < rings; ++j) {
      const double t = static_cast<double>(j) / (rings - 1);
      const Vec3 center = c.c1 + ((1.0 - t) * start + t * end) * c.axis;
      const double rho = (1.0 - t) * rho1 + t * rho2;
      const int n = std::max(3, static_cast<int>(std::ceil(2.0 * kPi * rho / spacing)));
      for (int k = 0; k < n; ++k) {
        const double angle = 2.0 * kPi * k / n;
        out.points.push_back(center + rho * (std::cos(angle) * u + std::sin(angle) * v));
        out.pieces.push_back(piece);
      }
    }
  }

  static void sample_triangle(const std::array<Vec3, 3>& t, double spacing, int piece,
                              BoundarySamples& out) {
    const double longest =
        std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing)));
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; i + j <= n; ++j) {
        out.points.push_back(t[0] + (t[1] - t[0]) * (double(i) / n) +
                             (t[2] - t[0]) * (double(j) / n));
        out.pieces.push_back(piece);
      }
    }
  }

  std::vector<Sphere> spheres_;
  std::vector<Cone> cones_;
  std::vector<Slab> slabs_;
  std::vector<std::array<Vec3, 3>> triangles_;  // tangent triangles of the slabs that have them
  std::vector<int> triangle_slab_;
  std::vector<std::uint64_t> solid_keys_, piece_keys_;
  std::vector<Box> solid_boxes_, piece_boxes_;
  std::optional<Bvh> solid_tree_, piece_tree_;  // built last: they refer to the box vectors
};

void check_shape(const SurfaceInput& shape) {
  if (shape.points.empty()) throw InvalidInput("shape has no point");
  const int n = static_cast<int>(shape.points.size());
  for (std::size_t f = 0; f < shape.faces.size(); ++f) {
    for (int v : shape.faces[f]) {
      if (v < 0 || v >= n) {
        throw InvalidInput("shape face " + std::to_string(f) + ": vertex index " +
                           std::to_string(v) + " out of range");
      }
    }
  }
}

// Input points followed by `count` area-weighted random points of the mesh's surface.
std::vector<Vec3> surface_samples(const SurfaceInput& shape, int count, unsigned seed) {
  std::vector<Vec3> samples = shape.points;
  if (!shape.is_mesh() || count <= 0) return samples;
  std::vector<double> cumulative_area;
  double total = 0.0;
  for (const auto& f : shape.faces) {
    const Vec3& a = shape.points[f[0]];
    total += 0.5 * (shape.points[f[1]] - a).cross(shape.points[f[2]] - a).norm();
    cumulative_area.push_back(total);
  }
  if (!(total > 0.0)) return samples;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int i = 0; i < count; ++i) {
    const double pick = uniform(rng) * total;
    const auto face =
        std::min(static_cast<std::size_t>(
                     std::upper_bound(cumulative_area.begin(), cumulative_area.end(), pick) -
                     cumulative_area.begin()),
                 shape.faces.size() - 1);
    const auto& f = shape.faces[face];
    const double r = std::sqrt(uniform(rng)), t = uniform(rng);
    samples.push_back((1.0 - r) * shape.points[f[0]] + r * (1.0 - t) * shape.points[f[1]] +
                      r * t * shape.points[f[2]]);
  }
  return samples;
}

// Distance to the input: exact point-to-triangle distance for a mesh, nearest point for a cloud.
class ShapeDistance {
 public:
  explicit ShapeDistance(const SurfaceInput& shape) : shape_(shape) {
    if (!shape.is_mesh()) {
      points_.emplace(shape.points);
      return;
    }
    boxes_.reserve(shape.faces.size());
    for (const auto& f : shape.faces) {
      boxes_.push_back(
          Box(shape.points[f[0]]).extend(shape.points[f[1]]).extend(shape.points[f[2]]));
    }
    triangles_.emplace(boxes_);
  }

  // Exact distances, or for a query farther than `stop_below` from the input some distance below
  // it (see Bvh::nearest).
  std::vector<double> operator()(const std::vector<Vec3>& queries,
                                 double stop_below = -kInfinity) const {
    std::vector<double> distances(queries.size());
    const auto count = static_cast<std::ptrdiff_t>(queries.size());
#pragma omp parallel
    {
      int near_face = -1;  // neighbouring queries are near the same face: it is tried first
#pragma omp for schedule(dynamic, 4096)
      for (std::ptrdiff_t i = 0; i < count; ++i)
        distances[i] = distance(queries[i], stop_below, near_face);
    }
    return distances;
  }

 private:
  double distance(const Vec3& q, double stop_below, int& near_face) const {
    if (points_) {
      double squared = 0.0;
      points_->nearest(q, &squared);
      return std::sqrt(squared);
    }
    return triangles_->nearest(
        q,
        [&](int face) {
          const auto& f = shape_.faces[face];
          return point_triangle_distance(q, shape_.points[f[0]], shape_.points[f[1]],
                                         shape_.points[f[2]]);
        },
        stop_below, &near_face);
  }

  const SurfaceInput& shape_;
  std::optional<KdTree> points_;
  std::vector<Box> boxes_;
  std::optional<Bvh> triangles_;  // refers to boxes_
};

std::pair<double, double> max_and_mean(const std::vector<double>& values) {
  double max = 0.0, sum = 0.0;
  for (double v : values) {
    max = std::max(max, v);
    sum += v;
  }
  return {max, values.empty() ? 0.0 : sum / static_cast<double>(values.size())};
}

// The point with the largest value (the first of equals); the origin when there is none.
Vec3 worst_point(const std::vector<Vec3>& points, const std::vector<double>& values) {
  if (values.empty()) return Vec3::Zero();
  return points[std::max_element(values.begin(), values.end()) - values.begin()];
}

}  // namespace

void EvalOptions::validate() const {
  if (surface_samples < -1) {
    throw InvalidOption("surface_samples must be -1 (as many as vertices) or >= 0");
  }
  if (!(boundary_spacing >= 1e-4 && boundary_spacing <= 0.1)) {
    throw InvalidOption("boundary_spacing must be in [1e-4, 0.1] (fraction of the diagonal)");
  }
  if (refined_samples < 1 || refined_samples > 100000) {
    throw InvalidOption("refined_samples must be in [1, 100000]");
  }
  if (!(inside_tolerance >= 0.0 && inside_tolerance <= 0.01)) {
    throw InvalidOption("inside_tolerance must be in [0, 0.01] (fraction of the diagonal)");
  }
}

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Closest point by Voronoi regions (Ericson, Real-Time Collision Detection, 5.1.5).
  const Vec3 ab = b - a, ac = c - a;
  if (!(ab.cross(ac).squaredNorm() > 1e-24 * ab.squaredNorm() * ac.squaredNorm())) {
    return std::min({point_segment_distance(p, a, b), point_segment_distance(p, b, c),
                     point_segment_distance(p, c, a)});
  }
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return ap.norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  }
  const double denominator = va + vb + vc;
  return (p - (a + ab * (vb / denominator) + ac * (vc / denominator))).norm();
}

double round_cone_signed_distance(const Vec3& p, const Sphere& a, const Sphere& b) {
  return Cone(a, b).signed_distance(p);
}

double slab_signed_distance(const Vec3& p, const Sphere& a, const Sphere& b, const Sphere& c) {
  return Slab(a, b, c).signed_distance(p);
}

bool slab_tangent_triangles(const Sphere& a, const Sphere& b, const Sphere& c,
                            std::array<std::array<Vec3, 3>, 2>& triangles) {
  const Slab slab(a, b, c);
  if (slab.has_planes) triangles = slab.triangles;
  return slab.has_planes;
}

std::vector<Vec3> envelope_samples(const MedialMesh& medial, double spacing, double tolerance) {
  const Envelope envelope(medial);
  return envelope.visible(envelope.sample_boundaries(spacing), tolerance).points;
}

std::vector<double> envelope_distances(const MedialMesh& medial, const std::vector<Vec3>& points) {
  const Envelope envelope(medial);
  std::vector<double> distances(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    distances[i] = envelope.boundary_distance(points[i]);
  return distances;
}

// What the last measured reconstruction left to reuse: distances and visibility depend only on
// the primitives involved, which are recognised by their keys (Envelope::piece_key, solid_key).
struct SurfaceSideCache {                    // surface -> medial
  std::vector<double> distance;              // of every surface sample, exact
  std::vector<std::uint64_t> nearest;        // the key of the piece at that distance
  std::unordered_set<std::uint64_t> pieces;  // keys of every piece then
};

constexpr std::uint64_t kUnknown = 0;  // a sample's hider not yet looked for
constexpr std::uint64_t kNone = std::numeric_limits<std::uint64_t>::max();  // a visible sample

struct PieceSamples {  // medial -> surface: the uniform samples of one boundary piece
  std::vector<Vec3> points;
  std::vector<std::uint64_t> hider;  // key of a solid the sample is hidden in; kNone, kUnknown
  std::vector<double> distance;      // to the input, exact; NaN until needed
};

struct Evaluator::Impl {
  Impl(const SurfaceInput& shape, const EvalOptions& options)
      : options(options), shape(shape), distance(shape) {}
  EvalOptions options;
  const SurfaceInput& shape;
  double diagonal = 0.0;
  std::vector<Vec3> samples;  // surface -> medial: the input points, then random ones
  ShapeDistance distance;     // medial -> surface
  SurfaceSideCache surface_side;
  std::unordered_map<std::uint64_t, PieceSamples> boundary_side;  // by piece key
  std::unordered_set<std::uint64_t> solids;  // keys of every solid of the last reconstruction
};

namespace {

// Validates before the Impl builds anything from the shape.
const SurfaceInput& checked(const SurfaceInput& shape, const EvalOptions& options) {
  options.validate();
  check_shape(shape);
  return shape;
}

}  // namespace

Evaluator::Evaluator(const SurfaceInput& shape, const EvalOptions& options)
    : impl_(std::make_unique<Impl>(checked(shape, options), options)) {
  Box bounds;
  for (const Vec3& p : shape.points) bounds.extend(p);
  impl_->diagonal = bounds.diagonal().norm();
  if (!std::isfinite(impl_->diagonal) || !(impl_->diagonal > 0.0)) {
    throw InvalidInput("shape has a non-finite coordinate or no extent");
  }
  const int random_count =
      options.surface_samples < 0 ? static_cast<int>(shape.points.size()) : options.surface_samples;
  impl_->samples = surface_samples(shape, random_count, options.seed);
}

Evaluator::~Evaluator() = default;

EvalResult evaluate(const SurfaceInput& shape, const MedialMesh& medial,
                    const EvalOptions& options) {
  return Evaluator(shape, options)(medial);
}

namespace {

// The primitives of `envelope` not among `known` keys, with a tree over their boxes.
struct FreshPrimitives {
  std::vector<int> ids;
  std::vector<Box> boxes;
  std::optional<Bvh> tree;  // refers to boxes
};

template <class KeyOf, class BoxOf>
void find_fresh(int count, const std::unordered_set<std::uint64_t>& known, KeyOf key_of,
                BoxOf box_of, FreshPrimitives& fresh) {
  for (int id = 0; id < count; ++id) {
    if (known.count(key_of(id))) continue;
    fresh.ids.push_back(id);
    fresh.boxes.push_back(box_of(id));
  }
  fresh.tree.emplace(fresh.boxes);
}

}  // namespace

EvalResult Evaluator::operator()(const MedialMesh& medial) {
  const EvalOptions& options = impl_->options;
  const std::vector<Vec3>& samples = impl_->samples;
  const ShapeDistance& distance = impl_->distance;
  const Envelope envelope(medial);
  EvalResult result;
  result.diagonal = impl_->diagonal;

  // Surface -> medial. A sample whose nearest piece is still there is at most as far as before,
  // and only the new pieces can be nearer.
  SurfaceSideCache& surface_side = impl_->surface_side;
  const bool reuse = !surface_side.distance.empty();
  FreshPrimitives fresh_pieces;
  if (reuse)
    find_fresh(
        envelope.piece_count(), surface_side.pieces, [&](int id) { return envelope.piece_key(id); },
        [&](int id) { return envelope.piece_box(id); }, fresh_pieces);
  std::unordered_set<std::uint64_t> pieces_now;
  for (int id = 0; id < envelope.piece_count(); ++id) pieces_now.insert(envelope.piece_key(id));
  surface_side.distance.resize(samples.size());
  surface_side.nearest.resize(samples.size());
  const auto sample_count = static_cast<std::ptrdiff_t>(samples.size());
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::ptrdiff_t i = 0; i < sample_count; ++i) {
    const Vec3& p = samples[i];
    double& d = surface_side.distance[i];
    std::uint64_t& nearest = surface_side.nearest[i];
    if (reuse && pieces_now.count(nearest)) {
      int item = -1;
      const double fresh = fresh_pieces.tree->nearest(
          p, [&](int k) { return envelope.piece_distance(fresh_pieces.ids[k], p); }, -kInfinity,
          &item);
      if (fresh < d) {
        d = fresh;
        nearest = envelope.piece_key(fresh_pieces.ids[item]);
      }
    } else {
      int piece = -1;
      d = envelope.nearest_piece(p, piece);
      nearest = envelope.piece_key(piece);
    }
  }
  surface_side.pieces = std::move(pieces_now);
  const std::vector<double>& to_medial = surface_side.distance;

  // Medial -> surface: uniform samples give the mean. The distance is 1-Lipschitz, so the maximum
  // can only exceed a sample's value by the spacing: refine (twice, 4x finer) around the samples
  // with the largest distances that could still hold it. The uniform samples of a piece that was
  // already there keep their distance, and their hider while it is there; a visible one can only
  // be hidden by a new solid.
  const double tolerance = options.inside_tolerance * result.diagonal;
  double spacing = options.boundary_spacing * result.diagonal;
  // Work and memory bounded whatever the medial mesh: primitives far larger than the shape
  // are sampled more coarsely (the counts grow as 1 / spacing²).
  const double expected = envelope.sample_count(spacing);
  if (expected > kMaxBoundarySamples) spacing *= std::sqrt(expected / kMaxBoundarySamples);
  FreshPrimitives fresh_solids;
  find_fresh(
      envelope.solid_count(), impl_->solids, [&](int id) { return envelope.solid_key(id); },
      [&](int id) { return envelope.solid_box(id); }, fresh_solids);
  std::unordered_set<std::uint64_t> solids_now;
  for (int id = 0; id < envelope.solid_count(); ++id) solids_now.insert(envelope.solid_key(id));
  std::unordered_map<std::uint64_t, PieceSamples> boundary_side;
  std::vector<std::pair<PieceSamples*, int>> by_piece;  // in piece order
  std::vector<std::pair<int, int>> flat;                // (index into by_piece, sample) to look at
  for (int piece = 0; piece < envelope.piece_count(); ++piece) {
    const std::uint64_t key = envelope.piece_key(piece);
    const auto [entry, first] = boundary_side.try_emplace(key);
    by_piece.emplace_back(&entry->second, piece);
    // Two coincident spheres give identical pieces: their samples are looked at once (a sample
    // on one is not inside the other).
    if (!first) continue;
    const auto known = impl_->boundary_side.find(key);
    if (known != impl_->boundary_side.end()) {
      entry->second = std::move(known->second);
    } else {
      BoundarySamples sampled;
      envelope.sample_piece(piece, spacing, sampled);
      entry->second.points = std::move(sampled.points);
      entry->second.hider.assign(entry->second.points.size(), kUnknown);
      entry->second.distance.assign(entry->second.points.size(),
                                    std::numeric_limits<double>::quiet_NaN());
    }
    for (int j = 0; j < static_cast<int>(entry->second.points.size()); ++j)
      flat.emplace_back(static_cast<int>(by_piece.size()) - 1, j);
  }
  const auto flat_count = static_cast<std::ptrdiff_t>(flat.size());
#pragma omp parallel
  {
    // Neighbouring samples of a piece are mostly hidden by the same solid. Which hider a sample
    // records does not matter: only whether it has one while that solid is there.
    int last_hider = -1;
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t f = 0; f < flat_count; ++f) {
      PieceSamples& entry = *by_piece[flat[f].first].first;
      const int piece = by_piece[flat[f].first].second, j = flat[f].second;
      const Vec3& p = entry.points[j];
      std::uint64_t& hider = entry.hider[j];
      if (hider != kUnknown && hider != kNone && solids_now.count(hider)) continue;
      if (hider == kNone) {
        const int owner = envelope.owner_solid(piece);
        fresh_solids.tree->any_containing(p, [&](int k) {
          const int id = fresh_solids.ids[k];
          if (id == owner || !envelope.deep_inside(id, p, tolerance)) return false;
          hider = envelope.solid_key(id);
          return true;
        });
        continue;
      }
      const int id = envelope.hider(p, piece, tolerance, last_hider);
      hider = id < 0 ? kNone : envelope.solid_key(id);
      if (id >= 0) last_hider = id;
    }
  }
  BoundarySamples boundary;
  std::vector<double*> distances;
  for (const auto& [entry, piece] : by_piece)
    for (std::size_t j = 0; j < entry->points.size(); ++j) {
      if (entry->hider[j] != kNone) continue;
      boundary.points.push_back(entry->points[j]);
      boundary.pieces.push_back(piece);
      distances.push_back(&entry->distance[j]);
    }
  std::vector<Vec3> unmeasured;  // visible samples without a distance yet, each once
  std::vector<double*> slots;
  for (auto& [key, entry] : boundary_side)
    for (std::size_t j = 0; j < entry.points.size(); ++j) {
      if (entry.hider[j] != kNone || !std::isnan(entry.distance[j])) continue;
      unmeasured.push_back(entry.points[j]);
      slots.push_back(&entry.distance[j]);
    }
  const std::vector<double> measured = distance(unmeasured);
  for (std::size_t k = 0; k < slots.size(); ++k) *slots[k] = measured[k];
  std::vector<double> to_surface(distances.size());
  for (std::size_t i = 0; i < distances.size(); ++i) to_surface[i] = *distances[i];
  impl_->boundary_side = std::move(boundary_side);
  impl_->solids = std::move(solids_now);
  std::tie(result.medial_to_surface_max, result.medial_to_surface_mean) = max_and_mean(to_surface);
  result.medial_to_surface_worst = worst_point(boundary.points, to_surface);
  result.boundary_sample_count = boundary.points.size();
  for (int round = 0; round < 2; ++round) {
    std::vector<std::size_t> order(boundary.points.size());
    std::iota(order.begin(), order.end(), 0);
    const std::size_t refined =
        std::min(order.size(), static_cast<std::size_t>(options.refined_samples));
    std::partial_sort(
        order.begin(), order.begin() + refined, order.end(), [&](std::size_t i, std::size_t j) {
          return to_surface[i] > to_surface[j] || (to_surface[i] == to_surface[j] && i < j);
        });
    BoundarySamples finer;
    for (std::size_t k = 0; k < refined; ++k) {
      const std::size_t i = order[k];
      if (to_surface[i] + spacing < result.medial_to_surface_max) break;
      envelope.sample_around(boundary.points[i], boundary.pieces[i], spacing, spacing / 4, finer);
    }
    spacing /= 4;
    if (round == 0) {  // done with the uniform samples: they go to the caller
      result.boundary_samples = std::move(boundary.points);
      result.boundary_error = std::move(to_surface);
    }
    boundary = envelope.visible(finer, tolerance);
    to_surface = distance(
        boundary.points, options.maxima_only ? result.medial_to_surface_max - spacing : -kInfinity);
    for (std::size_t i = 0; i < to_surface.size(); ++i) {
      if (to_surface[i] <= result.medial_to_surface_max) continue;
      result.medial_to_surface_max = to_surface[i];
      result.medial_to_surface_worst = boundary.points[i];
    }
  }

  std::tie(result.surface_to_medial_max, result.surface_to_medial_mean) = max_and_mean(to_medial);
  result.surface_to_medial_worst = worst_point(samples, to_medial);
  result.hausdorff = std::max(result.surface_to_medial_max, result.medial_to_surface_max);
  result.surface_sample_count = samples.size();
  if (options.maxima_only) {
    result.surface_to_medial_mean = result.medial_to_surface_mean = 0.0;
    result.boundary_samples.clear();
    result.boundary_error.clear();
    return result;
  }
  result.vertex_error.assign(to_medial.begin(), to_medial.begin() + impl_->shape.points.size());
  return result;
}

}  // namespace vmas
