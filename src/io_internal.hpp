#pragma once
// Helpers shared by the reading (io.cpp) and writing (io_write.cpp) halves of the IO stage.
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include "vmas/error.hpp"

namespace vmas::io_internal {

[[noreturn]] inline void fail(const std::string& path, const std::string& problem) {
  throw IoError(path + ": " + problem);
}

// Quotes a token for an error message, keeping the message short and on one printable line.
inline std::string quote(std::string_view token) {
  std::string text(token.substr(0, 40));
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return "'" + text + (token.size() > 40 ? "...'" : "'");
}

inline std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

inline bool host_is_little_endian() {
  const std::uint16_t probe = 1;
  char first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

}  // namespace vmas::io_internal
