/// @file cmd_stability.cpp
/// `clothbench stability`: the largest stable time step of each engine and integrator.

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/io/output_lock.hpp"
#include "harness/stability/stability_files.hpp"
#include "harness/stability/stability_sweep.hpp"
#include "support/option_checks.hpp"
#include "support/scenario_input.hpp"
#include "support/summaries.hpp"

namespace clothbench::cli {
namespace {

struct StabilityArgs {
  std::string scenario_path;           // empty: the embedded seed scene
  std::vector<std::string> overrides;  // --set KEY=VALUE
  bool quiet = false;
  double max_run_seconds = 0;  // s, 0: no limit
  StabilityOptions options;    // out_dir empty: out/<scenario name>
};

int execute_stability(StabilityArgs a) {
  StabilityOptions& o = a.options;
  o.progress = !a.quiet;
  Scenario sc = load_or_seed(a.scenario_path, a.overrides, o.engines);
  sc.max_run_seconds = a.max_run_seconds;
  if (o.out_dir.empty()) o.out_dir = "out/" + sc.name;
  refuse_overwriting_input(a.scenario_path, o.out_dir, kStabilitySidecar);
  const OutputLock lock(o.out_dir);
  const std::vector<StabilityRow> rows = run_stability(sc, o);
  std::cout << stability_summary(rows, o.method) << std::flush;
  if (o.progress) std::cerr << "wrote " << o.out_dir << "/stability.csv\n";
  return kExitOk;
}

}  // namespace

Command add_stability_command(CLI::App& app) {
  auto a = std::make_shared<StabilityArgs>();
  StabilityOptions& o = a->options;
  CLI::App* stability = app.add_subcommand(
      "stability",
      "Find the largest stable time step of each engine and integrator, measured by blow-up\n"
      "search (doubling, then bisection, over steps that divide the run's length) and by the\n"
      "growth of small perturbations (--method), and predicted by linear theory; writes\n"
      "stability.csv, whose rerun columns replay a blow-up row with `clothbench run SCENARIO\n"
      "<rerun>`, stability_modes/ROW.npy (the growing mode of row ROW, shape 3 by #P), and\n"
      "stability_scenario.toml, which --resume checks.");
  stability->add_option("scenario", a->scenario_path,
                        "scenario file (TOML); default: the embedded seed scene");
  stability->add_option("--out,-o", o.out_dir, "output folder (default: out/<scenario name>)");
  stability->add_option("--engine,-e", o.engines, "search only this engine (repeatable)")
      ->allow_extra_args(false);
  add_integrator_option(stability, o.integrators, "search");
  stability->add_option("--dt-max", o.dt_max, "largest dt tried (s)")
      ->capture_default_str()
      ->check(positive_number());
  stability
      ->add_option("--rel-tol", o.rel_tol,
                   "bisection stops when first_unstable / stable - 1 <= this (or when they are\n"
                   "one step count apart)")
      ->capture_default_str()
      ->check(positive_number());
  stability->add_option("--jobs,-j", o.jobs, "searches run at once (default: all cores)")
      ->check(positive_integer());
  stability->add_flag("--resume", o.resume,
                      "keep the rows already in stability.csv and search only the rest (refused\n"
                      "when the scenario, --set, --engine, --dt-max, --rel-tol, --method,\n"
                      "--perturbation or --growth-tol differ)");
  stability->add_option("--set,-s", a->overrides, "override a scenario key (repeatable)")
      ->allow_extra_args(false);
  o.method = StabilityMethod::both;  // every column map, check and the plots read, and growth
  add_growth_options(stability, o);
  add_shard_option(stability, o.shard);
  add_max_run_seconds(stability, a->max_run_seconds);
  add_allow_external(stability);
  stability->add_flag("--quiet,-q", a->quiet, "no progress on stderr");
  return {stability, [a] { return execute_stability(*a); }, true};
}

}  // namespace clothbench::cli
