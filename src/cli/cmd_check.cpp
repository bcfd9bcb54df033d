/// @file cmd_check.cpp
/// `clothbench check`: rerun scenarios and compare every gated quantity with its baseline.

#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/gate/gate_report.hpp"
#include "harness/gate/regression_check.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/output_lock.hpp"
#include "option_checks.hpp"
#include "scenario_input.hpp"

namespace clothbench::cli {
namespace {

struct CheckArgs {
  std::vector<std::string> paths;  // empty: every shipped scenario
  bool quiet = false;
  std::string junit_path, json_path;  // --junit, --json ("" : not written)
  CheckOptions options;
};

/// The --junit and --json files, opened before any run so that an unwritable path fails at
/// once (exit 2) instead of after the checks; they appear only when the checks are done.
struct ReportFiles {
  std::unique_ptr<AtomicFile> junit, json;
  explicit ReportFiles(const CheckArgs& a) {
    if (!a.junit_path.empty()) junit = std::make_unique<AtomicFile>(a.junit_path);
    if (!a.json_path.empty()) json = std::make_unique<AtomicFile>(a.json_path);
  }
  void write(const std::vector<Gate>& gates, const std::vector<ScenarioTiming>& timings) {
    if (junit) junit->write(junit_xml(gates, timings)), junit->commit();
    if (json) json->write(gates_json(gates)), json->commit();
  }
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
  ReportFiles reports(a);
  std::vector<Gate> all;
  std::vector<ScenarioTiming> timings;
  for (const std::string& p : a.paths) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<Gate> g = check_scenario(p, o);
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
    if (!g.empty()) timings.push_back({g.front().scenario, took.count()});
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
  reports.write(all, timings);
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
  auto* junit = check->add_option(
      "--junit", a->junit_path,
      "also write the gates as a JUnit XML report to FILE (one test case per gate: scenario, "
      "engine, quantity; a failure gives baseline, now and allowed)");
  auto* json =
      check->add_option("--json", a->json_path, "also write the gate table as JSON to FILE");
  auto* update = check->get_option("--update");
  junit->excludes(update), json->excludes(update);
  check->add_option("--jobs,-j", o.jobs, "threads for the stability searches")
      ->check(positive_integer());
  add_max_run_seconds(check, o.max_run_seconds);
  check->add_flag("--quiet,-q", a->quiet, "no progress on stderr");
  return {check, [a] { return execute_check(*a); }};
}

}  // namespace clothbench::cli
