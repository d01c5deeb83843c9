// vmas: command-line front end. Dispatches to a subcommand and maps errors to exit codes.
#include <boost/program_options/errors.hpp>
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
    "       vmas COMMAND --help\n"
    "       vmas --version\n";

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
