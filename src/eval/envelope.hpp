#pragma once
// The reconstruction of a medial mesh as the evaluator sees it: its primitives as solids (is
// this point hidden inside one?) and the pieces of their boundaries (how far is this point from
// the reconstruction's surface?), each with a key that recognises it in the next medial mesh.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "eval/bvh.hpp"
#include "eval/primitives.hpp"
#include "vmas/types.hpp"

namespace vmas {

// Samples on the boundary of the reconstruction: points of sphere surfaces, cone lateral surfaces
// and slab tangent triangles, `spacing` apart, that are not deeper than `tolerance` inside any
// other primitive. Validates `medial` like evaluate().
std::vector<Vec3> envelope_samples(const MedialMesh& medial, double spacing, double tolerance);

// Surface -> medial distance of each point: the smallest unsigned distance to the boundary of
// any primitive, as evaluate() measures it. Validates `medial` like evaluate().
std::vector<double> envelope_distances(const MedialMesh& medial, const std::vector<Vec3>& points);

// The indices, in order, of the points farther than `distance` from the boundary of every
// primitive (as envelope_distances measures, each search stopping at the first piece nearer).
// `go_on(share of the points searched)` is called from the calling thread between blocks of
// points; false throws Cancelled.
std::vector<int> points_farther_than(const MedialMesh& medial, const std::vector<Vec3>& points,
                                     double distance, const std::function<bool(double)>& go_on);

namespace internal __attribute__((visibility("hidden"))) {

// The indices of `points` along a Z-order curve over their bounding box (1024 cells a side).
std::vector<int> z_order(const std::vector<Vec3>& points);

// Throws InvalidInput for an empty medial mesh, an index out of range or repeated within an
// element, or a radius that is negative or not finite.
void check_medial(const MedialMesh& medial);

// Points on the boundaries of the primitives, with the boundary piece (Envelope's id) of each.
struct BoundarySamples {
  std::vector<Vec3> points;
  std::vector<int> pieces;
};

// What an Envelope id stands for. Pieces: sphere surfaces, then cone lateral surfaces, then
// tangent triangles; solids: spheres, then cones, then slabs. A sphere or cone has the same id as
// a piece and as a solid.
struct Piece {
  enum class Kind { Sphere, Cone, Triangle } kind;
  int index;  // into the spheres, the cones or the tangent triangles
};
struct Solid {
  enum class Kind { Sphere, Cone, Slab } kind;
  int index;  // into the spheres, the cones or the slabs
};

class Envelope {
 public:
  // Cones are those of all edges, face edges included, each once; a face given twice is one slab.
  explicit Envelope(const MedialMesh& medial);
  Envelope(const Envelope&) = delete;  // the trees refer to the box vectors
  Envelope& operator=(const Envelope&) = delete;

  int solid_count() const { return static_cast<int>(solid_keys_.size()); }
  int piece_count() const { return static_cast<int>(piece_keys_.size()); }
  Piece piece(int id) const;
  Solid solid(int id) const;
  // The same primitive in two envelopes has the same key, whatever its id: a hash of the exact
  // geometry of its spheres (never 0 or the largest value, which callers may use as marks).
  std::uint64_t solid_key(int solid) const { return solid_keys_[solid]; }
  std::uint64_t piece_key(int piece) const { return piece_keys_[piece]; }
  const Box& solid_box(int solid) const { return solid_boxes_[solid]; }
  const Box& piece_box(int piece) const { return piece_boxes_[piece]; }
  int owner_solid(int piece) const;  // the solid whose boundary the piece is part of

  // Unsigned distance from p to the boundary piece.
  double piece_distance(int piece, const Vec3& p) const;
  // The nearest piece to p and its distance; with `stop_below`, possibly some piece nearer than
  // that instead (Bvh::nearest). `piece`: one likely to be near, tried first, or -1.
  double nearest_piece(const Vec3& p, int& piece, double stop_below = -kInfinity) const;
  // Smallest unsigned distance from p to the boundary of any sphere, cone or tangent triangle.
  double boundary_distance(const Vec3& p) const {
    int piece = -1;
    return nearest_piece(p, piece);
  }
  // Whether p lies deeper than `tolerance` inside `solid`.
  bool deep_inside(int solid, const Vec3& p, double tolerance) const {
    return solid_signed_distance(solid, p) < -tolerance;
  }
  // A solid other than the owner of `piece` that p lies deeper than `tolerance` inside; -1 when
  // none does. `likely`: a solid to try first (neighbouring samples are mostly hidden by the same
  // one).
  int hider(const Vec3& p, int piece, double tolerance, int likely = -1) const;

  // Samples `spacing` apart on one boundary piece.
  void sample_piece(int piece, double spacing, BoundarySamples& out) const;
  // How many samples sample_piece would give over all pieces at `spacing` (an upper bound for
  // cones), counted in floating point: a sphere far larger than the shape must not overflow it.
  double sample_count(double spacing) const;
  // Samples `spacing` apart on every boundary piece, hidden ones included.
  BoundarySamples sample_boundaries(double spacing) const;
  // The samples that are not deeper than `tolerance` inside a primitive other than their own.
  BoundarySamples visible(const BoundarySamples& samples, double tolerance) const;
  // A grid of points `step` apart within `radius` of the sample p on the same piece (tangent
  // plane offsets projected back onto the piece), to refine the maximum around p.
  void sample_around(const Vec3& p, int piece, double radius, double step,
                     BoundarySamples& out) const;

 private:
  double solid_signed_distance(int solid, const Vec3& p) const;
  // Closest point of the piece to q (q near it); false when q falls outside a triangle.
  bool project_onto_piece(const Vec3& q, int piece, Vec3& projected) const;

  std::vector<Sphere> spheres_;
  std::vector<Cone> cones_;
  std::vector<Slab> slabs_;
  std::vector<std::array<Vec3, 3>> triangles_;  // tangent triangles of the slabs that have them
  std::vector<int> triangle_slab_;
  std::vector<std::uint64_t> solid_keys_, piece_keys_;
  std::vector<Box> solid_boxes_, piece_boxes_;
  std::optional<Bvh> solid_tree_, piece_tree_;  // built last: they refer to the box vectors
};

}  // namespace internal
}  // namespace vmas
