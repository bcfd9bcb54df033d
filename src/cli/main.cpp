/// @file main.cpp
/// The clothbench command: builds the command line from the subcommands (cmd_*.cpp), runs the
/// one chosen and turns what it throws into one line on stderr and an exit status
/// (exit_codes.hpp).

#include <CLI/CLI.hpp>
#include <csignal>
#include <exception>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/build_info.hpp"
#include "harness/runner.hpp"

using namespace clothbench;
using namespace clothbench::cli;

int main(int argc, char** argv) {
  bool keeps_finished_rows = false;  // what Ctrl-C leaves behind in the chosen command
  try {
    CLI::App app{
        "clothbench: a custom mass-spring cloth and Bullet's soft bodies on identical scenes,\n"
        "with energy, drape-shape and stability differences logged to CSV."};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("clothbench ") + kVersion);
    const std::vector<Command> commands = {add_run_command(app),      add_stability_command(app),
                                           add_accuracy_command(app), add_check_command(app),
                                           add_report_command(app),   add_list_command(app)};
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return app.exit(e) == 0 ? kExitOk : kExitUserError;
    }
    std::signal(SIGINT, [](int) { interrupt_requested() = true; });
    std::signal(SIGTERM, [](int) { interrupt_requested() = true; });
    for (const Command& c : commands) {
      if (!*c.app) continue;
      keeps_finished_rows = c.keeps_finished_rows;
      return c.execute();
    }
    return kExitInternalError;
  } catch (const Interrupted&) {
    // a run writes nothing until it is complete; a sweep has kept every finished row
    if (keeps_finished_rows)
      std::cerr << "clothbench: interrupted; the finished rows are kept (--resume goes on)\n";
    else
      std::cerr << "clothbench: interrupted; no output written\n";
    return kExitInterrupted;
  } catch (const std::invalid_argument& e) {
    std::cerr << "clothbench: " << e.what() << '\n';
    return kExitUserError;
  } catch (const std::runtime_error& e) {
    std::cerr << "clothbench: " << e.what() << '\n';
    return kExitUserError;
  } catch (const std::exception& e) {
    std::cerr << "clothbench: internal error: " << e.what() << '\n';
    return kExitInternalError;
  }
}
