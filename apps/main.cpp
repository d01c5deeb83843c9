// vmas: command-line front end. Dispatches to a subcommand and maps errors to exit codes.
#include <boost/program_options/errors.hpp>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "vmas/error.hpp"
#include "vmas/vmas.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace vmas::cli {

boost::program_options::variables_map parse_arguments(
    int argc, const char* const* argv, const boost::program_options::options_description& visible,
    const boost::program_options::options_description& hidden,
    const boost::program_options::positional_options_description& positional) {
  namespace po = boost::program_options;
  po::options_description all;
  all.add(visible).add(hidden);
  po::variables_map vm;
  po::store(po::command_line_parser(argc, argv).options(all).positional(positional).run(), vm);
  return vm;
}

void set_threads(int threads) {
  if (threads < 0) throw InvalidOption("--threads must be 0 or more");
#ifdef _OPENMP
  if (threads > 0) omp_set_num_threads(threads);
#endif
}

}  // namespace vmas::cli

namespace {

constexpr const char* kUsage =
    "vmas: skeletonize a shape by variational medial axis sampling\n"
    "\n"
    "usage: vmas skeletonize INPUT -o OUTPUT [--spheres N | --error E] [options]\n"
    "       vmas skeletonize INPUT... --output-dir DIR [options]\n"
    "       vmas eval SHAPE MEDIAL [--json] [--errors FILE] [--medial-errors FILE]\n"
    "       vmas convert INPUT OUTPUT [--medial]\n"
    "       vmas edit INPUT [-o OUTPUT] [--spheres N] [--port P]   (live editor in the browser)\n"
    "       vmas COMMAND --help\n"
    "       vmas --version\n";

// OpenMP threads that wait at a barrier spin by default, for up to a few hundred microseconds.
// On a machine that is busy with something else (a second vmas of a batch, say), the spinning
// thread takes the core from the one it waits for: two runs at once took 2.6 times as long as
// the same two one after the other, and one run beside a busy process 1.7 times as long as with
// --threads 1. Waiting passively costs about 3 % on an idle machine. libgomp reads the policy
// once, in its constructor: a function of the executable's preinit array runs before any
// library's constructor, so the setting is in place by then (a user's own OMP_WAIT_POLICY is
// left alone). Starting the process again with it set cost ~20 ms, 10 % of a small model's run.
void wait_passively_at_barriers(int, char**, char**) {
  setenv("OMP_WAIT_POLICY", "passive", /*replace=*/0);
}
__attribute__((section(".preinit_array"),
               used)) void (*const kWaitPassivelyAtBarriers)(int, char**,
                                                             char**) = &wait_passively_at_barriers;

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
    std::cout << kUsage;
    return argc < 2 ? 2 : 0;
  }
  if (std::strcmp(argv[1], "--version") == 0) {
    std::cout << "vmas " << vmas::version() << "\n";
    return 0;
  }
  const std::string command = argv[1];
  try {
    if (command == "skeletonize") return vmas::cli::skeletonize_command(argc - 1, argv + 1);
    if (command == "eval") return vmas::cli::eval_command(argc - 1, argv + 1);
    if (command == "convert") return vmas::cli::convert_command(argc - 1, argv + 1);
    if (command == "edit") return vmas::cli::edit_command(argc - 1, argv + 1);
    std::cerr << "vmas: unknown command '" << command << "' (try: vmas --help)\n";
    return 2;
  } catch (const boost::program_options::error& e) {
    std::cerr << "vmas " << command << ": " << e.what() << " (try: vmas " << command
              << " --help)\n";
    return 2;
  } catch (const vmas::InvalidOption& e) {
    // Named as typed on the command line: "--lambda must be ...".
    std::cerr << "vmas " << command << ": " << (e.option().empty() ? "" : "--") << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "vmas " << command << ": " << e.what() << "\n";
    return 1;
  }
}
