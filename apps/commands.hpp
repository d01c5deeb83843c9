#pragma once
// Subcommands of the `vmas` tool. Each parses its own options and returns the exit code:
// 0 success, 1 run error, 2 usage error. Errors escape as exceptions and main() prints them.
namespace vmas::cli {

int skeletonize_command(int argc, const char* const* argv);
int eval_command(int argc, const char* const* argv);
int convert_command(int argc, const char* const* argv);

// The --threads option of every subcommand: 0 keeps OpenMP's default (all cores).
void set_threads(int threads);

}  // namespace vmas::cli
