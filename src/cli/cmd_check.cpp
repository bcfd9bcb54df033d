/// @file cmd_check.cpp
/// `clothbench check`: rerun scenarios and compare every gated quantity with its baseline.

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/gate/gate_report.hpp"
#include "harness/gate/regression_check.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/output_lock.hpp"
#include "harness/io/user_error.hpp"
#include "support/option_checks.hpp"
#include "support/output_paths.hpp"
#include "support/scenario_input.hpp"

namespace clothbench::cli {
namespace {

struct CheckArgs {
  std::vector<std::string> paths;  // empty: every shipped scenario
  bool quiet = false;
  std::string junit_path, json_path;  // --junit, --json ("" : not written)
  bool no_ensemble = false;           // --no-ensemble: the ensembles' rows shown, not gated
  CheckOptions options;
};

/// The --junit and --json files, checked and opened before any run so that a path that must
/// not be written (an input, a folder, another command's folder, the other report's file) or
/// cannot be written fails at once (exit 2) instead of after the checks; they appear only when
/// the checks are done. "-" writes that report to standard output (and the gate table to
/// standard error).
struct ReportFiles {
  std::unique_ptr<AtomicFile> junit, json;
  bool junit_stdout = false, json_stdout = false;
  explicit ReportFiles(const CheckArgs& a) {
    check_output_files({{"--junit", a.junit_path}, {"--json", a.json_path}},
                       {a.paths, {a.options.baseline_dir}});
    junit_stdout = a.junit_path == "-", json_stdout = a.json_path == "-";
    if (!a.junit_path.empty() && !junit_stdout) junit = std::make_unique<AtomicFile>(a.junit_path);
    if (!a.json_path.empty() && !json_stdout) json = std::make_unique<AtomicFile>(a.json_path);
  }
  /// Where the gate table goes: standard error when a report takes standard output.
  std::ostream& table_stream() const { return junit_stdout || json_stdout ? std::cerr : std::cout; }
  void write(const std::vector<Gate>& gates, const std::vector<ScenarioTiming>& timings) {
    if (junit) junit->write(junit_xml(gates, timings)), junit->commit();
    if (json) json->write(gates_json(gates)), json->commit();
    if (junit_stdout) std::cout << junit_xml(gates, timings) << std::flush;
    if (json_stdout) std::cout << gates_json(gates) << std::flush;
  }
};

/// Throws UserError when two of the scenarios are one file or share a name: the name labels
/// every gate, so the table, the JUnit file and the JSON would count one scenario twice.
void refuse_duplicate_scenarios(const CheckArgs& a) {
  std::map<std::string, std::string> by_name;  // scenario name -> its file
  std::set<std::filesystem::path> files;
  for (const std::string& p : a.paths) {
    std::error_code ec;
    const std::filesystem::path file = std::filesystem::weakly_canonical(p, ec);
    if (!ec && !files.insert(file).second)
      throw UserError("check: the scenario " + p + " is given twice; give each file once");
    const std::string name = load_or_seed(p, a.options.overrides, {}).name;
    const auto [at, fresh] = by_name.emplace(name, p);
    if (!fresh)
      throw UserError("check: the scenarios " + at->second + " and " + p + " are both named \"" +
                      name +
                      "\" (the name labels their gates); give each its own name or check them "
                      "one at a time");
  }
}

int execute_check(CheckArgs a) {
  CheckOptions& o = a.options;
  o.progress = !a.quiet;
  o.ensemble = !a.no_ensemble;
  if (a.paths.empty()) a.paths = shipped_scenarios();
  refuse_duplicate_scenarios(a);
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
  reports.table_stream() << format_gates(all) << long(all.size()) - failed - ungated
                         << " gates passed, " << failed << " failed, " << ungated << " not gated\n";
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
      "engine, quantity; a failure gives baseline, now and allowed); - for standard output");
  auto* json = check->add_option(
      "--json", a->json_path, "also write the gate table as JSON to FILE; - for standard output");
  auto* update = check->get_option("--update");
  junit->excludes(update), json->excludes(update);
  check->add_option("--jobs,-j", o.jobs, "threads for the stability searches and ensembles")
      ->check(positive_integer());
  auto* ensemble = check->add_flag(
      "--ensemble", o.ensemble,
      "run the ensembles of the rows tolerances.toml gates by ensemble ([ensemble.<engine>]) "
      "and gate their means by Welch's t-test (the default)");
  check
      ->add_flag("--no-ensemble", a->no_ensemble,
                 "show the rows gated by ensemble without running their ensembles or gating "
                 "them, a quicker pass (--update records them all the same)")
      ->excludes(ensemble);
  check->add_option("--ensemble-seed", o.ensemble_seed,
                    "seed of the ensemble members' perturbations (default 0: the recorded "
                    "members; another seed draws new ones, to measure the false-alarm rate)");
  add_max_run_seconds(check, o.max_run_seconds);
  add_allow_external(check);
  check->add_flag("--quiet,-q", a->quiet, "no progress on stderr");
  return {check, [a] { return execute_check(*a); }};
}

}  // namespace clothbench::cli
