// OFF reader (OFF, NOFF, COFF; a file without faces is a point cloud).
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "io/internal.hpp"

namespace vmas::io_internal {

SurfaceInput parse_off(const std::string& path, std::string_view text) {
  LineTokenizer lines(path, text);
  std::vector<std::string_view> tokens;
  if (!lines.next(tokens)) fail(path, "bad header: no OFF line");
  const std::string_view keyword = tokens[0];
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF")
    lines.fail("bad header: expected OFF, NOFF or COFF, found " + quote(keyword));
  // NOFF promises a normal after each vertex; files that say NOFF but give none load without.
  const bool normals_announced =
      keyword.substr(0, keyword.size() - 3).find('N') != std::string_view::npos;
  std::size_t first = 1;
  if (tokens.size() == 1) {
    if (!lines.next(tokens)) fail(path, "bad header: no vertex and face counts");
    first = 0;
  }
  if (tokens.size() < first + 2) lines.fail("bad header: expected vertex and face counts");
  const std::size_t vertex_count = lines.count(tokens[first]);
  const std::size_t face_count = lines.count(tokens[first + 1]);

  PointSink sink;
  for (std::size_t i = 0; i < vertex_count; ++i) {
    if (!lines.next(tokens))
      fail(path,
           "truncated: " + std::to_string(i) + " of " + std::to_string(vertex_count) + " vertices");
    if (tokens.size() < 3) lines.fail("expected x y z");
    if (normals_announced && tokens.size() >= 6)
      sink.add_with_normal(lines.vec3(tokens, 0), lines.vec3(tokens, 3));
    else
      sink.add(lines.vec3(tokens, 0));
  }
  std::vector<double> polygon;
  for (std::size_t i = 0; i < face_count; ++i) {
    if (!lines.next(tokens))
      fail(path,
           "truncated: " + std::to_string(i) + " of " + std::to_string(face_count) + " faces");
    const std::size_t size = lines.count(tokens[0]);
    if (size > tokens.size() - 1) lines.fail("face lists fewer indices than its size");
    polygon.clear();
    for (std::size_t k = 1; k <= size; ++k) polygon.push_back(lines.integer(tokens[k]));
    const std::string problem = add_polygon(polygon, vertex_count, sink.faces());
    if (!problem.empty()) lines.fail(problem);
  }
  return sink.finish();
}

}  // namespace vmas::io_internal
