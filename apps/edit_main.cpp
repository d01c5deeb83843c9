// vmas-edit: the live editor, started by `vmas edit` (apps/main.cpp says why it is a program
// of its own); run directly, it takes the same arguments.
#include "commands.hpp"

int main(int argc, char** argv) {
  vmas::cli::restart_with_process_settings(argv);
  return vmas::cli::run_command("edit", vmas::cli::edit_command, argc, argv);
}
