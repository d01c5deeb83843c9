#include <stdexcept>

#include "commands.hpp"

namespace vmas::cli {
int skeletonize_command(int, const char* const*) { throw std::runtime_error("not implemented yet"); }
}  // namespace vmas::cli
