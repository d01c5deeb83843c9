// XYZ reader (.xyz/.txt: x y z or x y z nx ny nz per line).
#include <string>
#include <string_view>
#include <vector>

#include "io_internal.hpp"

namespace vmas::io_internal {

SurfaceInput parse_xyz(const std::string& path, std::string_view text) {
  LineTokenizer lines(path, text);
  std::vector<std::string_view> tokens;
  PointSink sink;
  while (lines.next(tokens)) {
    if (tokens.size() == 3)
      sink.add(lines.vec3(tokens, 0));
    else if (tokens.size() == 6)
      sink.add_with_normal(lines.vec3(tokens, 0), lines.vec3(tokens, 3));
    else
      lines.fail("expected 3 or 6 columns (x y z [nx ny nz]), found " +
                 std::to_string(tokens.size()));
  }
  return sink.finish();
}

}  // namespace vmas::io_internal
