// Tests of the connectivity stage (src/optimise/connectivity.cpp).
#include <gtest/gtest.h>

#include <set>

#include "optimise/connectivity.hpp"
#include "test_shapes.hpp"
#include "vmas/skeletonizer.hpp"

namespace vmas {
namespace {

TEST(Connectivity, SymmetricValidEdgesAndCliqueFaces) {
  const Shape shape = build_shape(test::icosphere(Vec3::Zero(), 1.0, 3), {});
  std::vector<int> labels(shape.size());
  // Octants: 8 clusters; neighbouring octants share a face of the octant cube.
  for (int v = 0; v < shape.size(); ++v) {
    const Vec3& p = shape.points[v];
    labels[v] = (p.x() > 1e-9) + 2 * (p.y() > 1e-9) + 4 * (p.z() > 1e-9);
  }
  const auto adjacency = cluster_adjacency(shape, labels, 8);
  for (int a = 0; a < 8; ++a)
    for (int b : adjacency[a]) {
      EXPECT_NE(a, b);
      EXPECT_TRUE(std::binary_search(adjacency[b].begin(), adjacency[b].end(), a));
    }
  const MedialMesh mesh = build_medial_mesh(std::vector<Sphere>(8), adjacency);
  std::set<std::pair<int, int>> edges;
  for (const auto& e : mesh.edges) {
    EXPECT_LT(e[0], e[1]);
    EXPECT_TRUE(edges.insert({e[0], e[1]}).second);
  }
  for (const auto& f : mesh.faces) {
    EXPECT_TRUE(edges.count({f[0], f[1]}) && edges.count({f[1], f[2]}) &&
                edges.count({f[0], f[2]}));
  }
  // Every octant touches at least its three face-neighbours.
  for (int a = 0; a < 8; ++a) EXPECT_GE(adjacency[a].size(), 3u);
}

}  // namespace
}  // namespace vmas
