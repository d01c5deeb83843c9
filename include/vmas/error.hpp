#pragma once
// Exceptions thrown at the library's boundaries. Messages are one line and name the file or
// parameter at fault, so the CLI can print them as they are.
#include <stdexcept>
#include <string>

#pragma GCC visibility push(default)  // what the public headers declare is exported

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
// option() names the field at fault as a path from the struct validated ("lambda",
// "normals.k"; from vmas::Options: "run.lambda", "prepare.normals.k") and the message is that
// path and problem(), so that a front end can name the field its own way ("--lambda must be
// ...").
struct InvalidOption : Error {
  InvalidOption(const std::string& option, const std::string& problem)
      : Error(option + " " + problem), option_(option), problem_(problem) {}
  const std::string& option() const { return option_; }
  const std::string& problem() const { return problem_; }
  // The same problem, seen from the struct holding the one validated as its member `member`.
  InvalidOption within(const std::string& member) const {
    return option_.empty() ? *this : InvalidOption(member + "." + option_, problem_);
  }

 private:
  std::string option_, problem_;
};

// A call that does not fit the object it is made on: an id, key or vertex that names nothing,
// removing the last sphere, a state of another shape, a full edit queue. The caller's mistake,
// not a usage error of the command line.
struct InvalidArgument : Error {
  using Error::Error;
};

// Thrown by skeletonize() (and the stages that take a callback) when the progress callback
// returned false.
struct Cancelled : Error {
  Cancelled() : Error("cancelled") {}
};

}  // namespace vmas

#pragma GCC visibility pop
