// What both programs (vmas, and vmas-edit behind `vmas edit`) share: argument parsing, threads,
// the mapping of errors to messages and exit codes, and the restart with process settings.
#include <unistd.h>

#include <algorithm>
#include <boost/program_options/errors.hpp>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "commands.hpp"
#include "vmas/error.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace vmas::cli {

boost::program_options::variables_map parse_arguments(
    int argc, const char* const* argv, const boost::program_options::options_description& visible,
    const boost::program_options::options_description& hidden,
    const boost::program_options::positional_options_description& positional,
    std::vector<boost::program_options::option>* given) {
  namespace po = boost::program_options;
  po::options_description all;
  all.add(visible).add(hidden);
  po::variables_map vm;
  const po::parsed_options parsed =
      po::command_line_parser(argc, argv).options(all).positional(positional).run();
  po::store(parsed, vm);
  if (given) *given = parsed.options;
  return vm;
}

void set_threads(int threads) {
  if (threads < 0) throw InvalidOption("threads", "must be 0 or more");
#ifdef _OPENMP
  // More threads than cores only wait for each other (1000 threads ran 13 times slower).
  if (threads > 0) omp_set_num_threads(std::min(threads, omp_get_num_procs()));
#endif
}

namespace {

// The one-line message (after "vmas NAME: ") and the exit code of an error out of a command.
std::pair<std::string, int> describe(const std::string& name, const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const boost::program_options::error& e) {
    return {std::string(e.what()) + " (try: vmas " + name + " --help)", 2};
  } catch (const InvalidOption& e) {
    // Named as typed on the command line: "--lambda must be ...".
    return {"--" + flag_of(e.option()) + " " + e.problem(), 2};
  } catch (const UsageError& e) {
    return {e.what(), 2};
  } catch (const std::exception& e) {
    return {e.what(), 1};
  } catch (...) {
    return {"unknown error", 1};
  }
}

bool asks_for_json(int argc, const char* const* argv) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--json") return true;
  return false;
}

}  // namespace

int run_command(const std::string& name, int (*command)(int, const char* const*), int argc,
                const char* const* argv) {
  std::exception_ptr error;
  bool json_printed = false;
  try {
    return command(argc, argv);
  } catch (const JsonPrinted& printed) {
    error = printed.error;
    json_printed = true;
  } catch (...) {
    error = std::current_exception();
  }
  const auto [message, exit_code] = describe(name, error);
  std::cerr << "vmas " << name << ": " << message << "\n";
  // --json promises one JSON object, also when the command line is wrong.
  if (!json_printed && asks_for_json(argc, argv))
    std::cout << nlohmann::json{{"vmas", version()}, {"error", message}}.dump(
                     -1, ' ', false, nlohmann::json::error_handler_t::replace)
              << std::endl;
  return exit_code;
}

// Two settings that libraries read once, when the process starts, so that they have to be in
// the environment before it does: they are set and the program starts again (~9 ms), each left
// alone when the user gave it. (Setting them from the executable's preinit array does not work:
// libc takes the environment from the stack again after that array has run.)
// - OMP_WAIT_POLICY=passive. OpenMP threads that wait at a barrier spin by default, for up to a
//   few hundred microseconds. On a machine that is busy with something else (a second vmas of a
//   batch, say), the spinning thread takes the core from the one it waits for: two runs at once
//   took 2.6 times as long as the same two one after the other, and one run beside a busy
//   process 1.7 times as long as with --threads 1.
// - glibc.malloc.hugetlb=1 in GLIBC_TUNABLES: malloc asks for transparent huge pages. Every
//   first touch of a 4 KB page costs a fault, and on a virtual machine a dear one: half the
//   faults or fewer, 5-13 % less time on the Table 1 meshes, peak memory +3 %.
void restart_with_process_settings(char** argv) {
  bool changed = false;
  if (std::getenv("OMP_WAIT_POLICY") == nullptr) {
    if (setenv("OMP_WAIT_POLICY", "passive", 1) != 0) return;
    changed = true;
  }
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string given = tunables == nullptr ? "" : tunables;
  if (given.find("glibc.malloc.hugetlb") == std::string::npos) {
    const std::string wanted = (given.empty() ? "" : given + ":") + "glibc.malloc.hugetlb=1";
    if (setenv("GLIBC_TUNABLES", wanted.c_str(), 1) != 0) return;
    changed = true;
  }
  if (changed) execv("/proc/self/exe", argv);  // returns only on failure: go on as we are
}

}  // namespace vmas::cli
