#pragma once
// Subcommands of the `vmas` tool. Each parses its own options and returns the exit code:
// 0 success, 1 run error, 2 usage error. Errors escape as exceptions; run_command prints them.
#include <boost/program_options.hpp>
#include <exception>
#include <string>
#include <vector>

#include "vmas/vmas.hpp"

namespace vmas::cli {

int skeletonize_command(int argc, const char* const* argv);
int eval_command(int argc, const char* const* argv);
int convert_command(int argc, const char* const* argv);
int edit_command(int argc, const char* const* argv);

// Parses a subcommand's arguments: the options it shows in --help (`visible`), and the
// positional ones (`positional`, declared in `hidden` so that --help leaves them out). Does not
// notify, so that --help works without them. `given`: the options as parsed, in order.
boost::program_options::variables_map parse_arguments(
    int argc, const char* const* argv, const boost::program_options::options_description& visible,
    const boost::program_options::options_description& hidden,
    const boost::program_options::positional_options_description& positional,
    std::vector<boost::program_options::option>* given = nullptr);

// The --threads option of every subcommand: 0 keeps OpenMP's default (all cores).
void set_threads(int threads);

// First thing in main(): starts the program again with passive waiting at OpenMP barriers and
// transparent huge pages for malloc, unless the user's environment says otherwise (apps/cli.cpp
// says why).
void restart_with_process_settings(char** argv);

// Runs a subcommand (`name` as typed after vmas) and maps what escapes it to a one-line message
// and an exit code: 2 for a usage error, 1 for any other. With --json among the arguments it
// also prints {"vmas", "error"} on stdout, unless the command has printed the failure's JSON
// itself and says so by throwing JsonPrinted.
struct JsonPrinted {
  std::exception_ptr error;  // what failed
};
int run_command(const std::string& name, int (*command)(int, const char* const*), int argc,
                const char* const* argv);

// Where a run's density comes from: --density (a file of one value per point, or a rule of
// vmas::density_by_rule) or --density-field (a field of the input); both empty: none.
struct DensitySource {
  std::string file_or_rule, field;
  bool is_rule() const;
  bool is_file() const { return !file_or_rule.empty() && !is_rule(); }
};
// The density `file_or_rule` gives the points of `surface` (a rule of vmas::density_by_rule, or
// a file of one value per line), unchecked.
std::vector<double> density_of(const std::string& file_or_rule, const SurfaceInput& surface);
// The input at `path` as stored, with the density `source` gives, checked (vmas::check_density):
// IoError naming the file at fault ("PATH: the density of point 7 is negative (-1)").
SurfaceInput read_with_density(const std::string& path, const DensitySource& source);

// The run's options (spheres, λ, denoising, normals, density ...), shared by skeletonize and edit.
struct RunOptionValues {
  Options options;
  std::string denoise = "auto";  // --denoise as typed
  DensitySource density;
};
// One option of a run, as `vmas skeletonize`, `vmas edit` and Python's keywords take it (the long
// name with '_' for '-'; lambda_). The one table of them gives the parser (add_run_options), the
// flag a message about a field names (flag_of) and Python's vmas.options(); docs/cli.md's option
// list, vmas.pyi's RunOptions and validate()'s ranges are checked against it
// (tests/python/test_options.py).
struct RunOption {
  const char* flag;   // "lambda,l": the long name, and a one-letter one after the comma
  const char* field;  // the field of vmas::Options it sets ("run.lambda"; "" for none)
  // What validate() accepts: "[a, b]", "[a, b)", "(a, b)", ">= a", or words and one of those
  // joined by " | " ("auto | off | [0, 0.5)"); "" for switches and text.
  const char* range;
  // How the parser reads its value into `values` (nullptr: a switch, no value).
  boost::program_options::value_semantic* (*value)(RunOptionValues& values,
                                                   const Options& defaults);
  const char* help;
};
const std::vector<RunOption>& run_option_table();
// Every row of run_option_table(), in its order (that of --help).
void add_run_options(boost::program_options::options_description& visible, RunOptionValues& values);
// After notify(): the flags and --denoise into `options`, then options.validate().
void finish_run_options(const boost::program_options::variables_map& vm, RunOptionValues& values);
// The flag (without dashes) that sets the field of vmas::Options that InvalidOption::option()
// names ("run.lambda": "lambda"); an option that is no such field is taken as a flag already
// (the commands' own, such as "port").
std::string flag_of(const std::string& option);

// A command line that cannot work whatever the data, about its paths rather than one option's
// value (InvalidOption's): an output that cannot be written, or that is also an input. Exit 2.
struct UsageError : Error {
  using Error::Error;
};

// Fails before any work is done when an output cannot possibly be written (a UsageError):
// `check` is vmas::check_output or vmas::check_medial_mesh_output.
void check_output_option(const std::string& path, void (*check)(const std::string&));
// Fails before any work when an output is one of the run's inputs or another of its outputs
// (vmas::check_distinct_files), as a UsageError. Empty paths (options not given) and `-`
// (standard input or output) are skipped.
void check_distinct_files_option(const std::vector<std::string>& inputs,
                                 const std::vector<std::string>& outputs);

}  // namespace vmas::cli
