// OBJ reader (v, vn, f; other records ignored).
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "io/internal.hpp"

namespace vmas::io_internal {

SurfaceInput parse_obj(const std::string& path, std::string_view text) {
  LineTokenizer lines(path, text);
  std::vector<std::string_view> tokens;
  SurfaceInput surface;
  std::vector<double> polygon;
  while (lines.next(tokens)) {
    const std::string_view keyword = tokens[0];
    if (keyword == "v" || keyword == "vn") {
      if (tokens.size() < 4) lines.fail("expected 3 coordinates after " + quote(keyword));
      (keyword == "v" ? surface.points : surface.normals).push_back(lines.vec3(tokens, 1));
    } else if (keyword == "f") {
      // A bare "f" (trimesh writes one for point clouds) holds no face.
      if (tokens.size() == 1) continue;
      polygon.clear();
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        const std::string_view token = tokens[k];
        const long long index = lines.integer(token.substr(0, token.find('/')));
        if (index == 0) lines.fail("vertex index 0 (OBJ indices start at 1)");
        // Negative indices count back from the last vertex read so far.
        polygon.push_back(static_cast<double>(
            index < 0 ? static_cast<long long>(surface.points.size()) + index : index - 1));
      }
      const std::string problem = add_polygon(polygon, surface.points.size(), surface.faces);
      if (!problem.empty()) lines.fail(problem);
    }
  }
  // Normals can be matched to points only in a cloud listing exactly one per point.
  if (surface.is_mesh() || surface.normals.size() != surface.points.size()) surface.normals.clear();
  return surface;
}

}  // namespace vmas::io_internal
