/// @file cmd_accuracy.cpp
/// `clothbench accuracy`: error against a fine rk4 reference and cost over a time-step sweep.

#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/io/output_lock.hpp"
#include "harness/io/user_error.hpp"
#include "harness/sweeps/accuracy_sweep.hpp"
#include "support/option_checks.hpp"
#include "support/scenario_input.hpp"

namespace clothbench::cli {
namespace {

struct AccuracyArgs {
  std::string scenario_path;           // empty: the embedded seed scene
  std::vector<std::string> overrides;  // --set KEY=VALUE
  bool quiet = false;
  double max_run_seconds = 0;              // s, 0: no limit
  std::string dts_text, resolutions_text;  // comma-separated lists, parsed into options
  AccuracyOptions options;                 // out_dir empty: out/<scenario name>-accuracy
};

// a comma-separated list of positive numbers; throws UserError naming the option
template <class T>
std::vector<T> parse_list(const std::string& text, const std::string& option) {
  std::vector<T> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::istringstream in(item);
    T v{};
    if (!(in >> v) || !(in >> std::ws).eof() || !(v > T(0)))
      throw UserError(option + ": expected positive numbers separated by commas, got \"" + item +
                      "\"");
    out.push_back(v);
  }
  return out;
}

int execute_accuracy(AccuracyArgs a) {
  AccuracyOptions& o = a.options;
  o.progress = !a.quiet;
  o.dts = parse_list<double>(a.dts_text, "--dts");
  o.resolutions = parse_list<int>(a.resolutions_text, "--resolutions");
  Scenario sc = load_or_seed(a.scenario_path, a.overrides, o.engines);
  sc.max_run_seconds = a.max_run_seconds;
  if (o.out_dir.empty()) o.out_dir = "out/" + sc.name + "-accuracy";
  refuse_overwriting_input(a.scenario_path, o.out_dir, "scenario.toml");
  const OutputLock lock(o.out_dir);
  const AccuracyReport report = run_accuracy(sc, o);
  std::cout << accuracy_summary(report) << std::flush;
  return kExitOk;
}

}  // namespace

Command add_accuracy_command(CLI::App& app) {
  auto a = std::make_shared<AccuracyArgs>();
  AccuracyOptions& o = a->options;
  CLI::App* accuracy = app.add_subcommand(
      "accuracy",
      "Error against a fine rk4 reference and cost, over a time-step sweep of every engine and\n"
      "integrator: work_precision.csv, convergence.csv (fitted orders), and with --tolerance the\n"
      "cheapest configuration that meets it (recommendation.csv).");
  accuracy->add_option("scenario", a->scenario_path,
                       "scenario file (TOML); default: the embedded seed scene");
  accuracy->add_option("--out,-o", o.out_dir,
                       "output folder (default: out/<scenario name>-accuracy)");
  accuracy->add_option("--engine,-e", o.engines, "sweep only this engine (repeatable)")
      ->allow_extra_args(false);
  add_integrator_option(accuracy, o.integrators, "sweep");
  auto* dts_opt = accuracy->add_option("--dts", a->dts_text,
                                       "time steps to sweep (s), comma separated, e.g. 1e-4,5e-5");
  accuracy
      ->add_option("--halvings", o.halvings,
                   "without --dts: this many time steps, halving from each engine's dt")
      ->capture_default_str()
      ->check(positive_integer())
      ->excludes(dts_opt);
  accuracy
      ->add_option(
          "--tolerance", o.tolerance,
          "error tolerance (m, RMS distance): recommend the cheapest configuration within it.\n"
          "Cheapest is counted, not timed, so it does not change with the machine or --jobs: per\n"
          "engine the fewest force evaluations + 3 x CG iterations (a CG iteration with its share\n"
          "of the Newton linearisation costs about 3 force evaluations), times particles; Bullet\n"
          "engines, whose work is not counted, the fewest steps x particles; ties go to the "
          "smaller\n"
          "error. Overall compares the engines' choices by that count when all are custom, and by\n"
          "wall time per simulated second when Bullet is among them (wall time stays in the CSV)")
      ->check(positive_number());
  accuracy
      ->add_option("--reference-dt", o.reference_dt,
                   "the time-step study's rk4 reference step (s): at most the smallest swept dt\n"
                   "and a quarter of rk4's predicted limit, dividing a frame (default: the\n"
                   "smallest swept dt / 4, or the largest step within that quarter). A coarser\n"
                   "reference is cheaper; its error floor in reference.csv says whether it is\n"
                   "fine enough. The resolution study keeps its own reference")
      ->check(positive_number());
  accuracy->add_option("--resolutions", a->resolutions_text,
                       "square grid sizes to compare at each engine's dt, e.g. 9,13,17,25,33");
  accuracy->add_option("--repeats", o.repeats, "wall time is the median of this many runs")
      ->capture_default_str()
      ->check(positive_integer());
  accuracy
      ->add_option("--jobs,-j", o.jobs,
                   "runs at once (default: all cores; timings are cleaner with 1)")
      ->check(positive_integer());
  accuracy->add_flag("--resume", o.resume,
                     "keep the rows already in the output folder and run only the rest");
  accuracy->add_option("--set,-s", a->overrides, "override a scenario key (repeatable)")
      ->allow_extra_args(false);
  add_shard_option(accuracy, o.shard);
  add_max_run_seconds(accuracy, a->max_run_seconds);
  add_allow_external(accuracy);
  accuracy->add_flag("--quiet,-q", a->quiet, "no progress on stderr");
  return {accuracy, [a] { return execute_accuracy(*a); }, true};
}

}  // namespace clothbench::cli
