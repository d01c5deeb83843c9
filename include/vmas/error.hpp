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
// When the value is one of vmas::Options, option() names it as the CLI spells it without its
// dashes ("lambda", "normal-k"), and the message starts with that name, so that a front end can
// point at its own spelling ("--lambda must be ...").
struct InvalidOption : Error {
  using Error::Error;
  InvalidOption(const std::string& option, const std::string& problem)
      : Error(option + " " + problem), option_(option) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// A call that does not fit the object it is made on: an id, key or vertex that names nothing,
// removing the last sphere, a state of another shape, a full edit queue. The caller's mistake,
// not a usage error of the command line.
struct InvalidArgument : Error {
  using Error::Error;
};

}  // namespace vmas
