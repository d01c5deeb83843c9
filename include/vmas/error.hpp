#pragma once
// Exceptions thrown at the library's boundaries. Messages are one line and name the file or
// parameter at fault, so the CLI can print them as they are.
#include <stdexcept>
#include <string>

namespace vmas {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A file could not be read or written (missing, unknown format, truncated, malformed).
struct IoError : Error {
  using Error::Error;
};

// Data the method cannot work with (empty cloud, a shape with no area, missing normals).
struct InvalidInput : Error {
  using Error::Error;
};

// An option value out of its range (thrown by the options structs' validate()); a usage error.
struct InvalidOption : Error {
  using Error::Error;
};

}  // namespace vmas
