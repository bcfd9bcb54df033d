/// @file cmd_run.cpp
/// `clothbench run`: every engine of a scenario on its scene, written to one output folder.

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/io/output_lock.hpp"
#include "harness/io/toml_text.hpp"
#include "harness/run/attribution.hpp"
#include "harness/run/runner.hpp"
#include "support/option_checks.hpp"
#include "support/scenario_input.hpp"
#include "support/summaries.hpp"

namespace clothbench::cli {
namespace {

struct RunArgs {
  std::string scenario_path;           // empty: the embedded seed scene
  std::string out;                     // empty: out/<scenario name>
  std::vector<std::string> engines;    // empty: every engine
  std::vector<std::string> overrides;  // --set KEY=VALUE
  bool quiet = false;
  bool explain = false;        // --explain: matched engines and attribution.csv
  double max_run_seconds = 0;  // s, 0: no limit
};

/// --explain: the program each external engine starts and how, one line each on stderr.
void explain_external_engines(const Scenario& sc) {
  for (const EngineSpec& e : sc.engines) {
    if (e.kind != EngineKind::external) continue;
    std::cerr << "engine " << e.name << " runs the external program:";
    for (const std::string& word : e.external.command) std::cerr << ' ' << toml_string(word);
    std::cerr << " (step_timeout = " << e.external.step_timeout
              << " s, share_cpu = " << (e.external.share_cpu ? "true" : "false") << ")\n";
  }
}

int execute_run(RunArgs a) {
  Scenario sc = load_or_seed(a.scenario_path, a.overrides, a.engines);
  sc.max_run_seconds = a.max_run_seconds;
  if (a.explain) add_matched_engines(sc, a.engines);
  if (a.explain) explain_external_engines(sc);
  if (a.out.empty()) a.out = "out/" + sc.name;
  refuse_overwriting_input(a.scenario_path, a.out, "scenario.toml");
  const OutputLock lock(a.out);
  RunOptions options;
  options.engines = a.engines;
  options.progress = !a.quiet;
  const RunResult result = run_scenario(sc, options);
  write_run(result, a.out);
  if (a.explain) write_attribution(result, a.out);
  if (!a.quiet)
    std::cerr << "wrote " << a.out << "/{frames,divergence,snapshots,summary"
              << (a.explain ? ",attribution" : "") << "}.csv, scenario.toml, run.json\n";
  std::cout << run_summary(result) << std::flush;
  // what the table's numbers are in, and where to look next (stderr: stdout stays a CSV)
  if (!a.quiet)
    std::cerr << "units: dt in s, us_per_step in microseconds of wall time, max_energy_error in "
                 "J, final_rms_vs_reference in m (RMS particle distance from "
              << sc.reference << " at the end)\n"
              << "next: clothbench report " << a.out << "   (plots and report.html of this run)\n";
  return kExitOk;
}

}  // namespace

Command add_run_command(CLI::App& app) {
  auto a = std::make_shared<RunArgs>();
  CLI::App* run = app.add_subcommand(
      "run",
      "Run every engine of a scenario on its scene and write frames, divergence, snapshots "
      "and summary CSVs.\nWithout SCENARIO: the course report's seed scene on several "
      "integrators.");
  run->add_option("scenario", a->scenario_path,
                  "scenario file (TOML); default: the embedded seed scene");
  run->add_option("--out,-o", a->out, "output folder (default: out/<scenario name>)");
  run->add_option("--engine,-e", a->engines,
                  "run only this engine (repeatable; the reference always runs)")
      ->allow_extra_args(false);
  run->add_option(
         "--set,-s", a->overrides,
         "override a scenario key, e.g. cloth.damping=0 or engine.custom-rk4.dt=2e-4 (repeatable)")
      ->allow_extra_args(false);
  add_max_run_seconds(run, a->max_run_seconds);
  add_allow_external(run);
  run->add_flag("--explain", a->explain,
                "for each Bullet engine also run the custom engine with its time scheme and dt "
                "(custom-as-<name>: imex-euler for bullet-deformable's explicit mode, "
                "implicit-euler for its implicit mode) and write attribution.csv, which splits "
                "the Bullet engine's distance from the reference into scheme_rms (reference vs "
                "that engine) and model_rms (that engine vs Bullet); for each external engine, "
                "show the program it runs");
  run->add_flag("--quiet,-q", a->quiet, "no progress on stderr");
  run->footer(
      "Exit status: 0 when every engine ran (an unstable run is a result), 2 for bad input, 70 "
      "for an internal error.");
  return {run, [a] { return execute_run(*a); }};
}

}  // namespace clothbench::cli
