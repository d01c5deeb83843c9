#pragma once
// The summary file of `vmas skeletonize --summary FILE`: one JSON line per input ever run into it,
// keyed by the line's "input", which each run merges its lines into and `--resume` reads to skip
// the inputs that are done. Several vmas processes may merge into one file at once (GNU parallel,
// a Slurm array): a merge holds an exclusive lock on FILE.lock and replaces FILE by a rename, so
// that a reader never sees half a file and no line is lost.
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace vmas::cli {

class BatchSummary {
 public:
  explicit BatchSummary(std::string path) : path_(std::move(path)) {}

  // The lines of FILE as it is now, by input (none when it does not exist yet).
  std::map<std::string, nlohmann::ordered_json> read() const;
  // Puts `line` (which has an "input") in place of that input's line, or after the others.
  // Lines of FILE that are not JSON objects with an "input" are kept as they are. IoError when
  // FILE or its lock cannot be written.
  void merge(const nlohmann::ordered_json& line) const;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Why the input of `line` (its line in a summary file; nullptr: it has none) is to run again with
// `options`: "" when that run needs no repeating, that is when the line has no error, was made
// with `options` (its "batch_options"), and `output` exists, is not empty and is newer than
// `input`; else the first of these that fails ("not run yet", "failed: MESSAGE", ...).
std::string reason_to_run(const nlohmann::ordered_json* line,
                          const std::vector<std::string>& options, const std::string& input,
                          const std::string& output);

}  // namespace vmas::cli
