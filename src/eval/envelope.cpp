#include "eval/envelope.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <string>

#include "core/radix_sort.hpp"
#include "core/sphere_lattice.hpp"
#include "vmas/error.hpp"

namespace vmas {
namespace internal {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// Order-free for the spheres of a cone or slab; `kind` keeps kinds apart.
std::uint64_t key_of(std::uint64_t kind, std::vector<std::uint64_t> parts) {
  if (kind == 1 || kind == 2) std::sort(parts.begin(), parts.end());
  std::uint64_t h = mix(kind + 0x9e3779b97f4a7c15ULL);
  for (std::uint64_t part : parts) h = mix(h ^ part);
  return std::clamp<std::uint64_t>(h, 2, std::numeric_limits<std::uint64_t>::max() - 1);
}

std::uint64_t key_of(const Sphere& s) {
  return key_of(0, {bits(s.center.x()), bits(s.center.y()), bits(s.center.z()), bits(s.radius)});
}

// About one sample per spacing² of area.
void sample_sphere(const Sphere& s, double spacing, int piece, BoundarySamples& out) {
  const double area = 4.0 * kPi * s.radius * s.radius;
  const int n = std::max(4, static_cast<int>(std::ceil(area / (spacing * spacing))));
  for (int i = 0; i < n; ++i) {
    out.points.push_back(s.center + s.radius * fibonacci_direction(i, n));
    out.pieces.push_back(piece);
  }
}

// Rings between the two circles where the lateral surface touches the spheres.
void sample_cone(const Cone& c, double spacing, int piece, BoundarySamples& out) {
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

void sample_triangle(const std::array<Vec3, 3>& t, double spacing, int piece,
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

// A Piece or Solid from its id: ids number the spheres, then the cones, then the third kind.
template <class Numbered>
Numbered numbered(int id, std::size_t spheres, std::size_t cones, typename Numbered::Kind third) {
  const int first_cone = static_cast<int>(spheres);
  const int first_third = static_cast<int>(spheres + cones);
  if (id < first_cone) return {Numbered::Kind::Sphere, id};
  if (id < first_third) return {Numbered::Kind::Cone, id - first_cone};
  return {third, id - first_third};
}

}  // namespace

std::vector<int> z_order(const std::vector<Vec3>& points) {
  Box box;
  for (const Vec3& p : points) box.extend(p);
  const Vec3 size = box.sizes().cwiseMax(1e-300);
  // The 10 bits of a cell coordinate spread to every third bit.
  const auto spread = [](std::uint64_t x) {
    x = (x | (x << 16)) & 0x30000ffULL;
    x = (x | (x << 8)) & 0x300f00fULL;
    x = (x | (x << 4)) & 0x30c30c3ULL;
    return (x | (x << 2)) & 0x9249249ULL;
  };
  std::vector<std::uint64_t> keys(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint64_t code = 0;
    for (int c = 0; c < 3; ++c) {
      const double cell = std::floor((points[i][c] - box.min()[c]) / size[c] * 1023.0 + 0.5);
      code |= spread(static_cast<std::uint64_t>(std::clamp(cell, 0.0, 1023.0))) << c;
    }
    keys[i] = (code << 32) | i;
  }
  internal::radix_sort(keys);
  std::vector<int> order(points.size());
  for (std::size_t k = 0; k < keys.size(); ++k)
    order[k] = static_cast<int>(keys[k] & 0xffffffffULL);
  return order;
}


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

Envelope::Envelope(const MedialMesh& medial) : spheres_(medial.spheres) {
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
  piece_boxes_.assign(solid_boxes_.begin(), solid_boxes_.begin() + spheres_.size() + cones_.size());
  for (const auto& t : triangles_) {
    piece_boxes_.push_back(Box(t[0]).extend(t[1]).extend(t[2]));
  }
  solid_tree_.emplace(solid_boxes_);
  piece_tree_.emplace(piece_boxes_);
}

Piece Envelope::piece(int id) const {
  return numbered<Piece>(id, spheres_.size(), cones_.size(), Piece::Kind::Triangle);
}

Solid Envelope::solid(int id) const {
  return numbered<Solid>(id, spheres_.size(), cones_.size(), Solid::Kind::Slab);
}

int Envelope::owner_solid(int id) const {
  const Piece p = piece(id);
  if (p.kind != Piece::Kind::Triangle) return id;
  return static_cast<int>(spheres_.size() + cones_.size()) + triangle_slab_[p.index];
}

double Envelope::piece_distance(int id, const Vec3& p) const {
  const Piece at = piece(id);
  switch (at.kind) {
    case Piece::Kind::Sphere:
      return std::abs((p - spheres_[at.index].center).norm() - spheres_[at.index].radius);
    case Piece::Kind::Cone:
      return std::abs(cones_[at.index].signed_distance(p));
    case Piece::Kind::Triangle:
      break;
  }
  const auto& t = triangles_[at.index];
  return point_triangle_distance(p, t[0], t[1], t[2]);
}

double Envelope::nearest_piece(const Vec3& p, int& piece, double stop_below) const {
  if (piece >= piece_count()) piece = -1;
  return piece_tree_->nearest(
      p, [&](int id) { return piece_distance(id, p); }, stop_below, &piece);
}

double Envelope::solid_signed_distance(int id, const Vec3& p) const {
  const Solid at = solid(id);
  switch (at.kind) {
    case Solid::Kind::Sphere:
      return (p - spheres_[at.index].center).norm() - spheres_[at.index].radius;
    case Solid::Kind::Cone:
      return cones_[at.index].signed_distance(p);
    case Solid::Kind::Slab:
      break;
  }
  return slabs_[at.index].signed_distance(p);
}

int Envelope::hider(const Vec3& p, int piece, double tolerance, int likely) const {
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

void Envelope::sample_piece(int id, double spacing, BoundarySamples& out) const {
  const Piece at = piece(id);
  switch (at.kind) {
    case Piece::Kind::Sphere:
      return sample_sphere(spheres_[at.index], spacing, id, out);
    case Piece::Kind::Cone:
      return sample_cone(cones_[at.index], spacing, id, out);
    case Piece::Kind::Triangle:
      return sample_triangle(triangles_[at.index], spacing, id, out);
  }
}

double Envelope::sample_count(double spacing) const {
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

BoundarySamples Envelope::sample_boundaries(double spacing) const {
  BoundarySamples samples;
  for (int piece = 0; piece < piece_count(); ++piece) sample_piece(piece, spacing, samples);
  return samples;
}

BoundarySamples Envelope::visible(const BoundarySamples& samples, double tolerance) const {
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

void Envelope::sample_around(const Vec3& p, int id, double radius, double step,
                             BoundarySamples& out) const {
  const Piece at = piece(id);
  Vec3 normal;
  switch (at.kind) {
    case Piece::Kind::Sphere:
      normal = (p - spheres_[at.index].center).normalized();
      break;
    case Piece::Kind::Cone: {
      const Cone& c = cones_[at.index];
      const Vec3 q = p - c.c1;
      normal = c.b * c.axis + c.a * (q - q.dot(c.axis) * c.axis).normalized();
      break;
    }
    case Piece::Kind::Triangle: {
      const auto& t = triangles_[at.index];
      normal = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
      break;
    }
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
      if (!project_onto_piece(q, id, projected)) continue;
      out.points.push_back(projected);
      out.pieces.push_back(id);
    }
  }
}

bool Envelope::project_onto_piece(const Vec3& q, int id, Vec3& projected) const {
  const Piece at = piece(id);
  if (at.kind == Piece::Kind::Sphere) {
    const Sphere& s = spheres_[at.index];
    projected = s.center + s.radius * (q - s.center).normalized();
    return true;
  }
  if (at.kind == Piece::Kind::Cone) {
    // In the (axial, radial) half-plane the lateral surface is a segment.
    const Cone& c = cones_[at.index];
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
  const auto& t = triangles_[at.index];
  const Vec3 e1 = t[1] - t[0], e2 = t[2] - t[0], v = q - t[0];
  const double d00 = e1.dot(e1), d01 = e1.dot(e2), d11 = e2.dot(e2);
  const double d20 = v.dot(e1), d21 = v.dot(e2), det = d00 * d11 - d01 * d01;
  const double b1 = (d11 * d20 - d01 * d21) / det, b2 = (d00 * d21 - d01 * d20) / det;
  projected = t[0] + b1 * e1 + b2 * e2;
  return b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0;
}

}  // namespace internal

namespace {

// Points searched between two calls of points_farther_than's `go_on`.
constexpr std::ptrdiff_t kFartherBlock = 1 << 16;

}  // namespace

std::vector<Vec3> envelope_samples(const MedialMesh& medial, double spacing, double tolerance) {
  const internal::Envelope envelope(medial);
  return envelope.visible(envelope.sample_boundaries(spacing), tolerance).points;
}

std::vector<double> envelope_distances(const MedialMesh& medial, const std::vector<Vec3>& points) {
  const internal::Envelope envelope(medial);
  std::vector<double> distances(points.size());
  const auto count = static_cast<std::ptrdiff_t>(points.size());
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::ptrdiff_t i = 0; i < count; ++i) distances[i] = envelope.boundary_distance(points[i]);
  return distances;
}

std::vector<int> points_farther_than(const MedialMesh& medial, const std::vector<Vec3>& points,
                                     double distance, const std::function<bool(double)>& go_on) {
  const internal::Envelope envelope(medial);
  const std::vector<int> visit = internal::z_order(points);
  std::vector<char> far(points.size(), 0);
  const auto count = static_cast<std::ptrdiff_t>(points.size());
  for (std::ptrdiff_t block = 0; block < count; block += kFartherBlock) {
    if (go_on && !go_on(double(block) / double(count))) throw Cancelled();
    const std::ptrdiff_t end = std::min(count, block + kFartherBlock);
#pragma omp parallel
    {
      int piece = -1;  // the last one found by this thread: neighbours in `visit` share it
#pragma omp for schedule(dynamic, 1024)
      for (std::ptrdiff_t k = block; k < end; ++k) {
        const int i = visit[k];
        // Stopped early, the distance is below `distance`; otherwise it is exact.
        far[i] = envelope.nearest_piece(points[i], piece, distance) > distance;
      }
    }
  }
  std::vector<int> farther;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (far[i]) farther.push_back(static_cast<int>(i));
  return farther;
}

}  // namespace vmas
