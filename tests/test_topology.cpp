// Betti numbers of medial meshes and the genus of closed meshes, exact on shapes built by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "optimise/topology.hpp"
#include "test_shapes.hpp"
#include "vmas/io.hpp"
#include "vmas/vmas.hpp"

namespace vmas {
namespace {

// The closed surface of a union of unit voxels (x, y) of a one-voxel-thick plate: each voxel
// face that borders no other voxel, as two triangles turning outward.
SurfaceInput voxel_plate(const std::set<std::pair<int, int>>& voxels) {
  SurfaceInput mesh;
  std::map<std::array<int, 3>, int> ids;
  const auto id = [&](int x, int y, int z) {
    const auto [entry, fresh] = ids.try_emplace({x, y, z}, static_cast<int>(mesh.points.size()));
    if (fresh) mesh.points.emplace_back(x, y, z);
    return entry->second;
  };
  // A unit square from `corner` spanned by u and v (u × v pointing outward).
  const auto square = [&](std::array<int, 3> c, std::array<int, 3> u, std::array<int, 3> v) {
    const int a = id(c[0], c[1], c[2]), b = id(c[0] + u[0], c[1] + u[1], c[2] + u[2]);
    const int d = id(c[0] + v[0], c[1] + v[1], c[2] + v[2]);
    const int e = id(c[0] + u[0] + v[0], c[1] + u[1] + v[1], c[2] + u[2] + v[2]);
    mesh.faces.push_back({a, b, e});
    mesh.faces.push_back({a, e, d});
  };
  for (const auto& [x, y] : voxels) {
    square({x, y, 1}, {1, 0, 0}, {0, 1, 0});  // top
    square({x, y, 0}, {0, 1, 0}, {1, 0, 0});  // bottom
    if (!voxels.count({x - 1, y})) square({x, y, 0}, {0, 0, 1}, {0, 1, 0});
    if (!voxels.count({x + 1, y})) square({x + 1, y, 0}, {0, 1, 0}, {0, 0, 1});
    if (!voxels.count({x, y - 1})) square({x, y, 0}, {1, 0, 0}, {0, 0, 1});
    if (!voxels.count({x, y + 1})) square({x, y + 1, 0}, {0, 0, 1}, {1, 0, 0});
  }
  return mesh;
}

SurfaceGenus genus_of(const SurfaceInput& mesh) {
  return surface_genus(mesh, mesh_defects(mesh.faces));
}

TEST(SurfaceGenus, OfATorusADoubleTorusAndASphereWithACavity) {
  EXPECT_EQ(genus_of(test::torus(1.0, 0.3, 24, 12)).genus, std::vector<int>{1});
  // A 5 × 3 plate with two holes: genus 2.
  std::set<std::pair<int, int>> plate;
  for (int x = 0; x < 5; ++x)
    for (int y = 0; y < 3; ++y)
      if (!(y == 1 && (x == 1 || x == 3))) plate.insert({x, y});
  const SurfaceGenus two = genus_of(voxel_plate(plate));
  ASSERT_TRUE(two.known) << two.why;
  EXPECT_EQ(two.genus, std::vector<int>{2});
  // A ball with a cavity: two pieces of genus 0 (the inner one turned inward).
  SurfaceInput shell = test::icosphere(Vec3::Zero(), 1.0, 2);
  SurfaceInput inner = test::icosphere(Vec3::Zero(), 0.5, 1);
  const int offset = static_cast<int>(shell.points.size());
  shell.points.insert(shell.points.end(), inner.points.begin(), inner.points.end());
  for (const auto& f : inner.faces) shell.faces.push_back({f[0] + offset, f[2] + offset, f[1] + offset});
  EXPECT_EQ(genus_of(shell).genus, (std::vector<int>{0, 0}));
  // Open: unknown, and why.
  SurfaceInput open = test::icosphere(Vec3::Zero(), 1.0, 2);
  open.faces.pop_back();
  const SurfaceGenus unknown = genus_of(open);
  EXPECT_FALSE(unknown.known);
  EXPECT_EQ(unknown.why, "the mesh is open");
}

MedialMesh spheres(int count) {
  MedialMesh mesh;
  for (int i = 0; i < count; ++i) mesh.spheres.push_back({Vec3(i, 0, 0), 0.1});
  return mesh;
}

TEST(MedialTopology, LoopsCavitiesAndDuplicatesOfHandMadeMeshes) {
  // A square of edges: one loop; filled by two triangles: none.
  MedialMesh square = spheres(4);
  square.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  MedialTopology t = medial_topology(square);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.loops, 1);
  EXPECT_EQ(t.cavities, 0);
  square.faces = {{0, 1, 2}, {0, 2, 3}};
  EXPECT_EQ(medial_topology(square).loops, 0);
  // The surface of a tetrahedron: a cavity, closed by its last triangle; a fifth sphere apart.
  MedialMesh tetrahedron = spheres(5);
  tetrahedron.faces = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  t = medial_topology(tetrahedron);
  EXPECT_EQ(t.components, 2);
  EXPECT_EQ(t.loops, 0);
  EXPECT_EQ(t.cavities, 1);
  EXPECT_EQ(t.closing_triangles, std::vector<int>{3});
  // Without the closing triangle (its edges kept): no cavity, the same pieces and loops.
  MedialMesh opened = tetrahedron;
  opened.faces.pop_back();
  opened.edges = {{1, 2}, {2, 3}, {1, 3}};
  t = medial_topology(opened);
  EXPECT_EQ(t.cavities, 0);
  EXPECT_EQ(t.loops, 0);
  EXPECT_EQ(t.components, 2);
  // A triangle listed twice (either way round) is one triangle and a duplicate, not a cavity.
  MedialMesh twice = spheres(3);
  twice.faces = {{0, 1, 2}, {2, 1, 0}};
  t = medial_topology(twice);
  EXPECT_EQ(t.duplicate_triangles, 1u);
  EXPECT_EQ(t.cavities, 0);
  EXPECT_EQ(t.loops, 0);
  // Two tetrahedra sharing a face: a cavity each.
  MedialMesh pair = spheres(5);
  pair.faces = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}, {0, 1, 4}, {0, 2, 4}, {1, 2, 4}};
  t = medial_topology(pair);
  EXPECT_EQ(t.cavities, 2);
  EXPECT_EQ(t.closing_triangles.size(), 2u);
}

// A torus at 60 spheres: its loop, and cavities that cluster adjacency closes: left out by
// default, the loop kept; kept (and reported) on request.
TEST(MedialTopology, CavitiesOfARunAreReportedAndLeftOutOnRequest) {
  const SurfaceInput torus = test::torus(1.0, 0.3, 48, 24);
  Options options;
  options.run.target.spheres = 60;
  options.run.open_cavities = false;
  const Result as_built = skeletonize(torus, options);
  EXPECT_EQ(as_built.input_genus.genus, std::vector<int>{1});
  EXPECT_EQ(as_built.topology.components, 1);
  EXPECT_EQ(as_built.topology.loops, 1);
  ASSERT_GT(as_built.topology.cavities, 0);
  const auto has_warning = [](const Result& r) {
    for (const Warning& w : r.warnings)
      if (w.code == "topology-mismatch") return true;
    return false;
  };
  EXPECT_TRUE(has_warning(as_built));
  options.run.open_cavities = true;
  const Result opened = skeletonize(torus, options);
  EXPECT_EQ(opened.topology.components, 1);
  EXPECT_EQ(opened.topology.loops, 1);
  EXPECT_EQ(opened.topology.cavities, 0);
  EXPECT_FALSE(has_warning(opened));
}

// `count` spheres of radius 0.05 on a circle of `radius` about `center` in the z = 0 plane,
// appended to `medial` and joined in a ring.
void add_ring(MedialMesh& medial, const Vec3& center, double radius, int count) {
  const int first = static_cast<int>(medial.spheres.size());
  for (int i = 0; i < count; ++i) {
    const double angle = 2.0 * M_PI * i / count;
    medial.spheres.push_back({center + radius * Vec3(std::cos(angle), std::sin(angle), 0.0), 0.05});
    medial.edges.push_back({first + i, first + (i + 1) % count});
  }
}

TEST(MedialTopology, ExtraLoopsAreFilledShortestFirst) {
  // A small ring (around a tube: 6 spheres 0.1 from its axis) and a big one (a handle: 10
  // spheres on a circle of 1), joined by an edge: two loops.
  MedialMesh medial;
  add_ring(medial, Vec3(0, 0, 0), 1.0, 10);
  add_ring(medial, Vec3(3, 0, 0), 0.1, 6);
  medial.edges.push_back({0, 10 + 3});
  ASSERT_EQ(medial_topology(medial).loops, 2);
  int filled = 0;
  // Genus 1: the handle's loop stays, the small ring is filled.
  const MedialMesh one = fill_extra_loops(medial, 1, &filled);
  EXPECT_EQ(filled, 1);
  const MedialTopology after = medial_topology(one);
  EXPECT_EQ(after.components, 1);
  EXPECT_EQ(after.loops, 1);
  EXPECT_EQ(after.cavities, 0);
  EXPECT_EQ(after.duplicate_triangles, 0u);
  EXPECT_EQ(one.spheres.size(), medial.spheres.size());
  EXPECT_EQ(one.faces.size(), 4u);  // a hexagon: four triangles, three new edges
  EXPECT_EQ(one.edges.size(), medial.edges.size() + 3);
  for (const auto& f : one.faces)
    for (int s : f) EXPECT_GE(s, 10) << "a triangle of the handle's loop";
  // Genus 0: both; a skeleton with no extra loop is returned as it was.
  const MedialMesh none = fill_extra_loops(medial, 0, &filled);
  EXPECT_EQ(filled, 2);
  EXPECT_EQ(medial_topology(none).loops, 0);
  EXPECT_EQ(medial_topology(none).cavities, 0);
  const MedialMesh same = fill_extra_loops(one, 1, &filled);
  EXPECT_EQ(filled, 0);
  EXPECT_EQ(same.faces.size(), one.faces.size());
  EXPECT_EQ(same.edges.size(), one.edges.size());
}

// Three spheres around a torus: their clusters touch pairwise, each pair across one cut of the
// ring, and meet nowhere, so cluster adjacency's triangle fills the handle's loop.
TEST(MedialTopology, AHandlesLoopThatATriangleFillsIsOpened) {
  const SurfaceInput torus = test::torus(1.0, 0.3, 48, 24);
  Options options;
  options.run.target.spheres = 3;
  options.loops_to_genus = false;
  const Result as_built = skeletonize(torus, options);
  ASSERT_EQ(as_built.topology.loops, 0) << "the case this test is about";
  ASSERT_EQ(as_built.medial_mesh.faces.size(), 1u);
  options.loops_to_genus = true;
  const Result opened = skeletonize(torus, options);
  EXPECT_EQ(opened.loops_opened, 1);
  EXPECT_EQ(opened.loops_filled, 0);
  EXPECT_EQ(opened.topology.components, 1);
  EXPECT_EQ(opened.topology.loops, 1);
  EXPECT_EQ(opened.topology.cavities, 0);
  EXPECT_TRUE(opened.medial_mesh.faces.empty());
  EXPECT_EQ(opened.medial_mesh.spheres.size(), 3u);
  for (const Warning& w : opened.warnings) EXPECT_NE(w.code, "topology-mismatch") << w.message;
}

}  // namespace
}  // namespace vmas
