// vmas: command-line front end. Dispatches to a subcommand; `vmas edit` starts vmas-edit.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "vmas/vmas.hpp"

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

// The live editor is a program of its own, vmas-edit, installed beside vmas: its HTTP server's
// libraries (Boost.Beast's, and those the editor needs) would otherwise load on every start of
// vmas, which most runs do not use.
// Returns only when it cannot be started.
int start_editor(int argc, char** argv) {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::string editor = (self.parent_path() / "vmas-edit").string();
  std::vector<char*> arguments(argv, argv + argc);
  arguments[0] = const_cast<char*>(editor.c_str());
  arguments.push_back(nullptr);
  execv(editor.c_str(), arguments.data());
  std::cerr << "vmas edit: cannot start the editor " << editor << ": " << std::strerror(errno)
            << " (it is installed beside vmas; in a build folder, `scripts/build` or `cmake "
               "--build build --target vmas-edit` builds it)\n";
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  vmas::cli::restart_with_process_settings(argv);
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
    std::cout << kUsage;
    return argc < 2 ? 2 : 0;
  }
  if (std::strcmp(argv[1], "--version") == 0) {
    std::cout << "vmas " << vmas::version() << "\n";
    return 0;
  }
  const std::string command = argv[1];
  using vmas::cli::run_command;
  if (command == "skeletonize")
    return run_command(command, vmas::cli::skeletonize_command, argc - 1, argv + 1);
  if (command == "eval") return run_command(command, vmas::cli::eval_command, argc - 1, argv + 1);
  if (command == "convert")
    return run_command(command, vmas::cli::convert_command, argc - 1, argv + 1);
  if (command == "edit") return start_editor(argc - 1, argv + 1);
  std::cerr << "vmas: unknown command '" << command << "' (try: vmas --help)\n";
  return 2;
}
