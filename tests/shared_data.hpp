#pragma once
// Where the tests and benchmarks find ../shared/data (the real models and scans): the folder
// VMAS_SHARED_DATA names in the environment, else the one beside the checkout (the build's
// VMAS_SHARED_DATA definition). Tests that need a file skip with a message naming it.
#include <cstdlib>
#include <filesystem>
#include <string>

namespace vmas::test {

inline std::string shared_data(const std::string& relative = "") {
  const char* override_dir = std::getenv("VMAS_SHARED_DATA");
  const std::filesystem::path root = override_dir ? override_dir : VMAS_SHARED_DATA;
  return relative.empty() ? root.string() : (root / relative).string();
}

}  // namespace vmas::test

// In a GoogleTest body: skips the test unless shared_data(relative) exists.
#define REQUIRE_SHARED_DATA(relative)                                                     \
  if (!std::filesystem::exists(::vmas::test::shared_data(relative)))                     \
  GTEST_SKIP() << "shared data not found: " << ::vmas::test::shared_data(relative)       \
               << " (set VMAS_SHARED_DATA to the folder holding meshes/ and scans/)"
