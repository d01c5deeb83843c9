#pragma once
// `-` as a path on the command line: standard input (INPUT -, with --input-format) or standard
// output (-o -, with --format), for every subcommand that reads or writes files.
#include <functional>
#include <string>
#include <vector>

namespace vmas::cli {

inline bool is_standard_stream(const std::string& path) { return path == "-"; }

// Calls use(path); for `-`, use(a copy of standard input in a temporary file with the extension
// `format`, so that the readers bound their work by what it holds as for any file), and the
// IoErrors it throws then name "standard input". The copy is removed afterwards.
void with_input_file(const std::string& path, const std::string& format,
                     const std::function<void(const std::string&)>& use);

// Writes `bytes` to standard output; IoError "standard output: cannot write (reason)".
void write_standard_output(const std::string& bytes);

// The usage rules of `-` among `inputs` (a usage error otherwise): at most one `-`, which needs
// --input-format, and --input-format only with a `-`.
void check_standard_input(const std::vector<std::string>& inputs, const std::string& input_format);

}  // namespace vmas::cli
