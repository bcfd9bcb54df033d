/// @file cmd_fit.cpp
/// `clothbench fit`: each engine's parameters fitted so that its metrics hit their targets.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "format/number_format.hpp"
#include "harness/io/output_lock.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/runner.hpp"
#include "harness/sweeps/fit_sweep.hpp"
#include "support/option_checks.hpp"
#include "support/scenario_input.hpp"

namespace clothbench::cli {
namespace {

struct FitArgs {
  std::vector<std::string> target_texts;  // METRIC=VALUE
  std::vector<std::string> range_texts;   // KEY=LO:HI
  std::string out_dir;
  bool quiet = false;
  bool run = false;  // --run: the fitted scenarios run, and fit.html comparing the engines
  FitOptions options;
};

/// A finite number from text, or a UserError naming the option and the text.
double number(const std::string& text, const std::string& option, const std::string& whole) {
  std::istringstream in(text);
  double v = NAN;
  if (text.empty() || !(in >> v) || !(in >> std::ws).eof() || !std::isfinite(v))
    throw UserError(option + " " + whole + ": expected a finite number, got \"" + text + "\"");
  return v;
}

/// METRIC=VALUE.
FitTarget parse_target(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw UserError("--target " + text + ": expected METRIC=VALUE, e.g. bending_length=0.03");
  return {text.substr(0, eq), number(text.substr(eq + 1), "--target", text)};
}

/// KEY=LO:HI with 0 < LO < HI.
FitRange parse_range(const std::string& text) {
  const size_t eq = text.find('='), colon = text.find(':', eq == std::string::npos ? 0 : eq);
  if (eq == std::string::npos || eq == 0 || colon == std::string::npos)
    throw UserError("--range " + text +
                    ": expected KEY=LO:HI, e.g. cloth.stiffness.bend=100:100000");
  FitRange r{text.substr(0, eq), number(text.substr(eq + 1, colon - eq - 1), "--range", text),
             number(text.substr(colon + 1), "--range", text)};
  if (!(r.lo > 0.0 && r.lo < r.hi))
    throw UserError("--range " + text + ": expected 0 < LO < HI (parameters are positive)");
  return r;
}

/// v with 4 significant digits, for the terminal (fit.csv has every digit).
std::string short_number(double v) {
  return cloth::significant(v, 4);
}

/// One line per row: what each engine reached, and why a fit stopped short.
void print_summary(const FitOutcome& outcome) {
  for (const FitRow& r : outcome.rows) {
    std::cout << r.engine << ": " << r.metric << " ";
    if (r.status == "no engine") {
      std::cout << "not fitted: " << r.note << "\n";
      continue;
    }
    std::cout << (std::isfinite(r.achieved) ? short_number(r.achieved) : "no value") << " (target "
              << short_number(r.target) << ")";
    if (r.runs > 0) std::cout << " at " << r.parameter << " = " << short_number(r.value);
    std::cout << ", " << r.runs << " runs, " << r.status;
    // the reason of a target unreachable before any run is on stderr already
    if (r.runs == 0 && r.status == "unreachable") {
      std::cout << ": the scenario cannot show it (why: on stderr)\n";
      continue;
    }
    if (r.status != "converged") std::cout << ": " << r.note << "; the best reached is given";
    std::cout << "\n";
  }
  std::cout << std::flush;
}

/// Each reason a target was unreachable before any run, once on stderr: what to change.
void explain_unmeasurable(const FitOutcome& outcome) {
  std::vector<std::string> said;
  for (const FitRow& r : outcome.rows) {
    if (r.status != "unreachable" || r.runs > 0) continue;
    if (std::find(said.begin(), said.end(), r.note) != said.end()) continue;
    said.push_back(r.note);
    std::cerr << "clothbench: fit: unreachable before any run: " << r.note << "\n";
  }
}

/// --run: each fitted scenario run (the engines fitted, with its reference) into
/// DIR/runs/<its file stem>, then analysis/fit_page.py writes DIR/fit.html comparing the
/// engines at the fitted values; returns the script's exit status.
int run_fitted(const FitOptions& o, const std::string& dir, bool quiet) {
  for (const std::string& path : o.scenarios) {
    const std::filesystem::path file(path);
    const std::string fitted = dir + "/fitted/" + file.filename().string();
    const std::string out = dir + "/runs/" + file.stem().string();
    const Scenario sc = load_or_seed(fitted, {}, o.engines);
    RunOptions ro;
    ro.engines = o.engines;
    ro.progress = !quiet;
    write_run(run_scenario(sc, ro), out);
    if (!quiet) std::cerr << "fit: ran " << fitted << " into " << out << "\n";
  }
  return run_analysis_script("fit_page.py", {dir});
}

int execute_fit(FitArgs a) {
  FitOptions& o = a.options;
  o.progress = !a.quiet;
  for (const std::string& t : a.target_texts) o.targets.push_back(parse_target(t));
  for (const std::string& r : a.range_texts) o.ranges.push_back(parse_range(r));
  if (o.targets.empty() && o.fabric.empty())
    throw UserError("fit: expected --target METRIC=VALUE or --fabric NAME");
  if (o.ranges.size() > o.targets.size())
    throw UserError("--range: " + std::to_string(o.ranges.size()) + " ranges for " +
                    std::to_string(o.targets.size()) +
                    " targets; the k-th --range names the k-th --target's parameter");
  // an input is never overwritten by its fitted copy
  for (const std::string& s : o.scenarios)
    refuse_overwriting_input(s, a.out_dir + "/fitted",
                             std::filesystem::path(s).filename().string());
  const OutputLock lock(a.out_dir);
  const FitOutcome outcome = run_fit(o);
  write_fit(o, outcome, a.out_dir);
  explain_unmeasurable(outcome);
  print_summary(outcome);
  return a.run ? run_fitted(o, a.out_dir, a.quiet) : kExitOk;
}

}  // namespace

Command add_fit_command(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  FitOptions& o = a->options;
  CLI::App* fit = app.add_subcommand(
      "fit",
      "Fits each engine's parameters so that its metrics hit their targets: each target's\n"
      "metric comes from the scenario whose [test] gives it, one parameter per target\n"
      "(one target: bracketing and secant steps in log parameter; several on one engine: a\n"
      "joint damped Gauss-Newton fit). Writes fit.csv and fitted/<scenario>,\n"
      "whose engines carry their fitted values (overrides = { ... }) for clothbench run.");
  fit->add_option("scenarios", o.scenarios, "scenario files (TOML)")->required();
  fit->add_option("--target,-t", a->target_texts,
                  "METRIC=VALUE, e.g. bending_length=0.03 (repeatable; m for lengths)")
      ->allow_extra_args(false);
  fit->add_option("--fabric", o.fabric,
                  "a preset of reference/fabrics/fabrics.toml: set as cloth.fabric on every\n"
                  "scenario, and its measured values the targets that --target leaves out\n"
                  "(bending_length from its warp rigidity, tensile_stiffness, drape_coefficient)");
  fit->add_option("--range,-r", a->range_texts,
                  "KEY=LO:HI: the k-th names the k-th target's parameter (a --set key; engine.KEY\n"
                  "for the engine's own) and bounds it; default: the metric's usual parameter\n"
                  "within 1e-4 to 1e4 times its value")
      ->allow_extra_args(false);
  fit->add_option("--engine,-e", o.engines, "fit only this engine (repeatable)")
      ->allow_extra_args(false);
  fit->add_option("--max-runs", o.max_runs,
                  "runs per engine and target at most (a joint fit: evaluations, each a run of\n"
                  "every scenario of its targets)")
      ->capture_default_str()
      ->check(positive_integer());
  fit->add_option("--tolerance", o.tolerance,
                  "relative tolerance of each metric (drape_coefficient: 0.03 absolute)")
      ->capture_default_str()
      ->check(positive_number());
  fit->add_option("--set,-s", o.overrides, "override a key of every scenario (repeatable)")
      ->allow_extra_args(false);
  fit->add_option("--out,-o", a->out_dir, "output folder")->required();
  fit->add_flag("--run", a->run,
                "then run each fitted scenario into OUT/runs/<its name> and write OUT/fit.html:\n"
                "the engines compared at the fitted values (analysis/fit_page.py)");
  fit->add_flag("--quiet,-q", a->quiet, "no progress on stderr");
  return {fit, [a] { return execute_fit(*a); }, false};
}

}  // namespace clothbench::cli
