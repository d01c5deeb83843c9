#pragma once
// How long a stage took, for the summaries' times.
#include <chrono>

namespace vmas {
namespace internal __attribute__((visibility("hidden"))) {

using Clock = std::chrono::steady_clock;

// Seconds from `start` until now.
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace internal
}  // namespace vmas
