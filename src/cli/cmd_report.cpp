/// @file cmd_report.cpp
/// `clothbench report`: analysis/report.py on an output folder, with Debian's python3 (for its
/// matplotlib); everything after `report` goes to the script. Also the script runner that
/// `clothbench export` shares.

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench::cli {

int run_analysis_script(const std::string& name, const std::vector<std::string>& args) {
  const std::string script = std::string(CLOTHBENCH_ANALYSIS_DIR) + "/" + name;
  const char* python =
      std::getenv("CLOTHBENCH_PYTHON") ? std::getenv("CLOTHBENCH_PYTHON") : "/usr/bin/python3";
  std::vector<std::string> argv_s = {python, script};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv_c;
  for (std::string& a : argv_s) argv_c.push_back(a.data());
  argv_c.push_back(nullptr);
  std::cout << std::flush;
  const pid_t pid = ::fork();
  if (pid == 0) {
    // a missing python is the user's to fix: one line and exit 2, as for a UserError
    ::execv(python, argv_c.data());
    std::cerr << "clothbench: cannot run " << python << ": " << std::strerror(errno) << '\n';
    std::_Exit(kExitUserError);
  }
  int status = 0;
  if (pid < 0 || ::waitpid(pid, &status, 0) < 0)
    throw UserError("cannot start " + std::string(python) + ": " + std::strerror(errno));
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

Command add_report_command(CLI::App& app) {
  CLI::App* report = app.add_subcommand(
      "report",
      "Plots and a self-contained report.html from an output folder (runs analysis/report.py\n"
      "with /usr/bin/python3). Everything after `report` goes to the script: DIR\n"
      "[--compare DIR2] [--labels A,B] [--out OUTDIR] [--svg] [--snapshot-times LIST]\n"
      "[--tolerance E] [--movie]; `clothbench report --help` shows the script's own help.");
  report->set_help_flag();  // --help goes to the script, whose help lists its options
  report->allow_extras();
  report->prefix_command();
  return {report, [report] { return run_analysis_script("report.py", report->remaining()); }};
}

}  // namespace clothbench::cli
