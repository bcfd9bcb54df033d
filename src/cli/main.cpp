/// @file main.cpp
/// The clothbench command: builds the command line from the subcommands (cmd_*.cpp), runs the
/// one chosen and turns what it throws into one line on stderr and an exit status
/// (exit_codes.hpp): a UserError is the user's to fix, anything else is a bug in clothbench.

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/build_info.hpp"
#include "harness/run/runner.hpp"
#include "support/option_checks.hpp"

namespace {

using namespace clothbench;
using namespace clothbench::cli;

// text on one line: a line break would split the one-line error
std::string one_line(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}

int internal_error(const std::string& what) {
  std::cerr << "clothbench: internal error (a bug in clothbench): " << one_line(what)
            << "; please report it with the command line, the scenario file and the output of "
               "`clothbench --version`\n";
  return kExitInternalError;
}

// test hook: CLOTHBENCH_TEST_INTERNAL_ERROR=1 makes any command fail as a bug would, so that
// tests/cli can check exit status 70 and its message (no command line can cause a bug on purpose)
void throw_if_internal_error_requested() {
  const char* hook = std::getenv("CLOTHBENCH_TEST_INTERNAL_ERROR");
  if (hook && std::string(hook) == "1")
    throw std::logic_error("CLOTHBENCH_TEST_INTERNAL_ERROR=1 is set (a test hook)");
}

}  // namespace

int main(int argc, char** argv) {
  bool keeps_finished_rows = false;  // what Ctrl-C leaves behind in the chosen command
  try {
    CLI::App app{
        "clothbench: a custom mass-spring cloth and Bullet's soft bodies on identical scenes,\n"
        "with energy, drape-shape and stability differences logged to CSV."};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("clothbench ") + kVersion);
    const std::vector<Command> commands = {
        add_run_command(app),    add_stability_command(app), add_accuracy_command(app),
        add_check_command(app),  add_map_command(app),       add_merge_command(app),
        add_report_command(app), add_export_command(app),    add_gallery_command(app),
        add_list_command(app),   add_schema_command(app),    add_fit_command(app)};
    require_known_command(app, argc, argv);
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      // --help and --version print as CLI11 does; an error is one line in clothbench's form
      if (e.get_exit_code() == 0) return app.exit(e);
      const bool named = argc > 1 && argv[1][0] != '-';
      std::cerr << "clothbench: " << one_line(e.what()) << " (see clothbench "
                << (named ? std::string(argv[1]) + " " : std::string()) << "--help)\n";
      return kExitUserError;
    }
    // the first Ctrl-C stops at the next step; a second one (a step stuck inside an engine)
    // ends the process at once: outputs appear only when complete, so none is half written
    const auto on_signal = [](int) {
      if (interrupt_requested().exchange(true)) std::_Exit(kExitInterrupted);
    };
    interrupt_requested() = false;  // its static is made here, never first in a handler
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    throw_if_internal_error_requested();
    for (const Command& c : commands) {
      if (!*c.app) continue;
      keeps_finished_rows = c.keeps_finished_rows;
      return c.execute();
    }
    throw std::logic_error("no subcommand chosen although one is required");
  } catch (const Interrupted&) {
    // a run writes nothing until it is complete; a sweep has kept every finished row
    if (keeps_finished_rows)
      std::cerr << "clothbench: interrupted; the finished rows are kept (--resume goes on)\n";
    else
      std::cerr << "clothbench: interrupted; no output written\n";
    return kExitInterrupted;
  } catch (const UserError& e) {
    std::cerr << "clothbench: " << one_line(e.what()) << '\n';
    return kExitUserError;
  } catch (const std::bad_alloc&) {
    // not a bug: the input asked for more than the machine has
    std::cerr << "clothbench: out of memory: this scene or sweep needs more memory than the "
                 "machine could give; use fewer particles (cloth.particles), fewer parallel "
                 "runs (-j) or a shorter duration\n";
    return kExitUserError;
  } catch (const std::exception& e) {
    return internal_error(e.what());
  } catch (...) {
    return internal_error("an exception that is not a std::exception");
  }
}
