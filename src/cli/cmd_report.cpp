/// @file cmd_report.cpp
/// `clothbench report`: analysis/report.py on an output folder, with Debian's python3 (for its
/// matplotlib); everything after `report` goes to the script. Also the script runner that
/// `clothbench export` shares.

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench::cli {

namespace {

// the script's process and the first signal that came while it ran, for the handler
volatile sig_atomic_t g_child = 0;
volatile sig_atomic_t g_signal = 0;

/// While the script runs, SIGINT and SIGTERM go on to it (a terminal's Ctrl-C reaches it
/// anyway; a kill of clothbench alone would not), and clothbench waits for it to end.
extern "C" void forward_signal(int sig) {
  if (g_signal == 0) g_signal = sig;
  if (g_child > 0) ::kill(pid_t(g_child), sig);
}

/// Waits for the script, forwarding signals to it; restores the old handlers when it ends.
int wait_forwarding(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR)
      throw UserError(std::string("cannot wait for the report script: ") + std::strerror(errno));
  }
  return status;
}

}  // namespace

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
  // signals that come before the child exists wait until it does (then go to it)
  sigset_t block, old_mask;
  sigemptyset(&block);
  sigaddset(&block, SIGINT);
  sigaddset(&block, SIGTERM);
  ::sigprocmask(SIG_BLOCK, &block, &old_mask);
  struct sigaction forward {
  }, old_int{}, old_term{};
  forward.sa_handler = forward_signal;
  sigemptyset(&forward.sa_mask);
  ::sigaction(SIGINT, &forward, &old_int);
  ::sigaction(SIGTERM, &forward, &old_term);
  g_signal = 0;
  const pid_t pid = ::fork();
  if (pid == 0) {
    // the script gets the default handlers and an unblocked mask
    ::signal(SIGINT, SIG_DFL), ::signal(SIGTERM, SIG_DFL);
    ::sigprocmask(SIG_SETMASK, &old_mask, nullptr);
    // a missing python is the user's to fix: one line and exit 2, as for a UserError
    ::execv(python, argv_c.data());
    std::cerr << "clothbench: cannot run " << python << ": " << std::strerror(errno) << '\n';
    std::_Exit(kExitUserError);
  }
  g_child = pid > 0 ? pid : 0;
  ::sigprocmask(SIG_SETMASK, &old_mask, nullptr);
  if (pid < 0) throw UserError("cannot start " + std::string(python) + ": " + std::strerror(errno));
  const int status = wait_forwarding(pid);
  g_child = 0;
  ::sigaction(SIGINT, &old_int, nullptr);
  ::sigaction(SIGTERM, &old_term, nullptr);
  // interrupted: 130 for Ctrl-C, 143 for SIGTERM, whatever the script made of it
  if (g_signal != 0) {
    std::cerr << "clothbench: interrupted; the script was stopped\n";
    return 128 + g_signal;
  }
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
