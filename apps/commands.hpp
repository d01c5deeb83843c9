#pragma once
// Subcommands of the `vmas` tool. Each parses its own options and returns the exit code:
// 0 success, 1 run error, 2 usage error. Errors escape as exceptions and main() prints them.
#include <boost/program_options.hpp>

namespace vmas::cli {

int skeletonize_command(int argc, const char* const* argv);
int eval_command(int argc, const char* const* argv);
int convert_command(int argc, const char* const* argv);

// Parses a subcommand's arguments: the options it shows in --help (`visible`), and the
// positional ones (`positional`, declared in `hidden` so that --help leaves them out). Does not
// notify, so that --help works without them.
boost::program_options::variables_map parse_arguments(
    int argc, const char* const* argv, const boost::program_options::options_description& visible,
    const boost::program_options::options_description& hidden,
    const boost::program_options::positional_options_description& positional);

// The --threads option of every subcommand: 0 keeps OpenMP's default (all cores).
void set_threads(int threads);

}  // namespace vmas::cli
