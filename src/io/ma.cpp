// .ma reader (Q-MAT medial meshes).
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "io/internal.hpp"

namespace vmas::io_internal {

MedialMesh parse_ma(const std::string& path, std::string_view text) {
  LineTokenizer lines(path, text);
  std::vector<std::string_view> tokens;
  if (!lines.next(tokens) || tokens.size() < 3)
    fail(path, "bad header: expected 'vertex_count edge_count face_count'");
  const std::size_t counts[3] = {lines.count(tokens[0]), lines.count(tokens[1]),
                                 lines.count(tokens[2])};
  MedialMesh mesh;
  const auto index = [&](std::string_view token) {
    int value = 0;
    if (!to_index(static_cast<double>(lines.integer(token)), counts[0], value))
      lines.fail("vertex index " + std::string(token) + " out of range (" +
                 std::to_string(counts[0]) + " vertices)");
    return value;
  };
  while (lines.next(tokens)) {
    const std::string_view kind = tokens[0];
    const std::size_t needed = kind == "v" ? 5 : kind == "e" ? 3 : kind == "f" ? 4 : 0;
    if (needed == 0) lines.fail("unknown record " + quote(kind) + " (expected v, e or f)");
    if (tokens.size() < needed) lines.fail("expected " + std::to_string(needed - 1) + " values");
    if (kind == "v") {
      const Sphere sphere{lines.vec3(tokens, 1), lines.number(tokens[4])};
      if (!in_range(sphere)) lines.fail(kSphereOutOfRange);
      mesh.spheres.push_back(sphere);
    } else if (kind == "e") {
      mesh.edges.push_back({index(tokens[1]), index(tokens[2])});
    } else {
      mesh.faces.push_back({index(tokens[1]), index(tokens[2]), index(tokens[3])});
    }
  }
  const std::size_t found[3] = {mesh.spheres.size(), mesh.edges.size(), mesh.faces.size()};
  const char* const kNames[3] = {"vertices", "edges", "faces"};
  for (int k = 0; k < 3; ++k)
    if (found[k] != counts[k])
      fail(path, "header announces " + std::to_string(counts[k]) + " " + kNames[k] + " but " +
                     std::to_string(found[k]) + " were found");
  return mesh;
}

}  // namespace vmas::io_internal
