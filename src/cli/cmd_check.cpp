/// @file cmd_check.cpp
/// `clothbench check`: rerun scenarios and compare every gated quantity with its baseline.

#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/output_lock.hpp"
#include "harness/regression_check.hpp"
#include "option_checks.hpp"
#include "scenario_input.hpp"

namespace clothbench::cli {
namespace {

struct CheckArgs {
  std::vector<std::string> paths;  // empty: every shipped scenario
  bool quiet = false;
  CheckOptions options;
};

int execute_check(CheckArgs a) {
  CheckOptions& o = a.options;
  o.progress = !a.quiet;
  if (a.paths.empty()) a.paths = shipped_scenarios();
  // --update writes the baselines: one command at a time
  std::unique_ptr<OutputLock> lock;
  PendingBaselines pending;  // all scenarios' new baselines appear together, or none
  if (o.update) {
    lock = std::make_unique<OutputLock>(o.baseline_dir);
    o.pending = &pending;
  }
  std::vector<Gate> all;
  for (const std::string& p : a.paths) {
    const std::vector<Gate> g = check_scenario(p, o);
    all.insert(all.end(), g.begin(), g.end());
  }
  const long failed = std::count_if(all.begin(), all.end(), [](const Gate& g) { return !g.pass; });
  if (o.update) {
    pending.commit();
    std::cout << (all.empty() ? std::string("baselines recorded; nothing changed\n")
                              : "baselines recorded; what changed:\n" + format_gates(all));
    return kExitOk;
  }
  const long ungated =
      std::count_if(all.begin(), all.end(), [](const Gate& g) { return !g.gated; });
  std::cout << format_gates(all) << long(all.size()) - failed - ungated << " gates passed, "
            << failed << " failed, " << ungated << " not gated\n";
  return failed > 0 ? kExitGateFailed : kExitOk;
}

}  // namespace

Command add_check_command(CLI::App& app) {
  auto a = std::make_shared<CheckArgs>();
  CheckOptions& o = a->options;
  o.baseline_dir = CLOTHBENCH_BASELINE_DIR;
  CLI::App* check = app.add_subcommand(
      "check",
      "Rerun scenarios and compare every gated quantity with its recorded baseline (final shape,\n"
      "energy error, stability, divergence from the reference, force evaluations, CG\n"
      "iterations). Exit status 1 when any gate fails. --update records new baselines.");
  check->add_option("scenarios", a->paths, "scenario files (default: every shipped scenario)");
  check->add_option("--baseline,-b", o.baseline_dir, "baseline folder (one subfolder per scenario)")
      ->capture_default_str();
  check->add_flag("--update", o.update,
                  "record the current results as the baseline and print what changed "
                  "(metrics, final shape RMS per engine, stability limits)");
  check->add_flag("--record-perturbed", o.record_perturbed,
                  "let --update record a baseline with --set overrides applied (refused "
                  "without this flag)");
  check
      ->add_option("--set,-s", o.overrides,
                   "override a scenario key in every scenario (repeatable)")
      ->allow_extra_args(false);
  check->add_option("--jobs,-j", o.jobs, "threads for the stability searches")
      ->check(positive_integer());
  add_max_run_seconds(check, o.max_run_seconds);
  check->add_flag("--quiet,-q", a->quiet, "no progress on stderr");
  return {check, [a] { return execute_check(*a); }};
}

}  // namespace clothbench::cli
