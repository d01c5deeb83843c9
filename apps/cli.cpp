// What both programs (vmas, and vmas-edit behind `vmas edit`) share: argument parsing, threads,
// the mapping of errors to messages and exit codes, and passive waiting at OpenMP barriers.
#include <unistd.h>

#include <boost/program_options/errors.hpp>
#include <cstdlib>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "vmas/error.hpp"

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

int run_command(const std::string& name, int (*command)(int, const char* const*), int argc,
                const char* const* argv) {
  try {
    return command(argc, argv);
  } catch (const boost::program_options::error& e) {
    std::cerr << "vmas " << name << ": " << e.what() << " (try: vmas " << name << " --help)\n";
    return 2;
  } catch (const InvalidOption& e) {
    // Named as typed on the command line: "--lambda must be ...".
    std::cerr << "vmas " << name << ": " << (e.option().empty() ? "" : "--") << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "vmas " << name << ": " << e.what() << "\n";
    return 1;
  }
}

// OpenMP threads that wait at a barrier spin by default, for up to a few hundred microseconds.
// On a machine that is busy with something else (a second vmas of a batch, say), the spinning
// thread takes the core from the one it waits for: two runs at once took 2.6 times as long as
// the same two one after the other, and one run beside a busy process 1.7 times as long as with
// --threads 1. Waiting passively costs about 3 % on an idle machine. libgomp reads the policy
// once, when it is loaded, so it has to be in the environment before the process starts: set
// it and start again (a user's own OMP_WAIT_POLICY is left alone). Setting it earlier from the
// executable's preinit array does not work: libc takes the environment from the stack again
// after that array has run.
void wait_passively_at_barriers(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  if (setenv("OMP_WAIT_POLICY", "passive", 1) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: go on as we are
}

}  // namespace vmas::cli
