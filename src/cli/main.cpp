/// @file main.cpp
/// The clothbench command: argument parsing and error reporting only; the work is in harness.

#include <sys/wait.h>
#include <unistd.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "cloth/integrator.hpp"
#include "harness/accuracy_sweep.hpp"
#include "harness/csv_writer.hpp"
#include "harness/engine_factory.hpp"
#include "harness/regression_check.hpp"
#include "harness/runner.hpp"
#include "harness/scenario_loader.hpp"
#include "harness/stability_sweep.hpp"

namespace {

using namespace clothbench;

// exit codes
constexpr int kOk = 0, kInternal = 1, kBadInput = 2, kInterrupted = 130;

// a comma-separated list of numbers; throws std::invalid_argument naming the option
template <class T>
std::vector<T> parse_list(const std::string& text, const std::string& option) {
  std::vector<T> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::istringstream in(item);
    T v{};
    if (!(in >> v) || !(in >> std::ws).eof() || !(v > T(0)))
      throw std::invalid_argument(
          option + ": expected positive numbers separated by commas, got \"" + item + "\"");
    out.push_back(v);
  }
  return out;
}

/// The scenario at path (the embedded seed without one), keeping the engines named in only
/// (and the reference), so an engine left out need not be able to model an overridden scene.
Scenario load(const std::string& path, const std::vector<std::string>& overrides,
              const std::vector<std::string>& only) {
  if (path.empty())
    return parse_scenario(embedded_default_scenario(), "<embedded seed_sphere_drape>", overrides,
                          only);
  return load_scenario(path, overrides, only);
}

int cmd_run(const std::string& path, std::string out, const std::vector<std::string>& engines,
            const std::vector<std::string>& overrides, bool quiet) {
  const Scenario sc = load(path, overrides, engines);
  if (out.empty()) out = "out/" + sc.name;
  RunOptions options;
  options.engines = engines;
  options.progress = !quiet;
  const RunResult result = run_scenario(sc, options);
  write_run(result, out);
  if (!quiet)
    std::cerr << "wrote " << out
              << "/{frames,divergence,snapshots,summary}.csv, scenario.toml, run.json\n";
  // the summary table on stdout
  std::cout << "engine,integrator,dt,stable,us_per_step,max_energy_error,final_rms_vs_reference\n";
  for (size_t i = 0; i < result.runs.size(); ++i) {
    const EngineRun& r = result.runs[i];
    const auto& d = result.divergence[i];
    std::cout << r.spec.name << ','
              << (r.spec.kind == EngineKind::custom ? cloth::integrator_name(r.spec.solver.integrator)
                                                    : engine_kind_name(r.spec.kind))
              << ',' << format_double(r.spec.dt) << ',' << (r.stable ? "yes" : "no") << ','
              << format_double(
                     std::round(1e7 * r.wall_s / std::max<double>(1, double(r.counters.steps))) /
                     10)
              << ',' << format_double(r.max_energy_error) << ','
              << (d.empty() ? std::string("") : format_double(d.back().rms_distance)) << '\n';
  }
  return kOk;
}

int cmd_stability(const std::string& path, const std::vector<std::string>& overrides,
                  StabilityOptions o) {
  const Scenario sc = load(path, overrides, o.engines);
  if (o.out_dir.empty()) o.out_dir = "out/" + sc.name;
  const std::vector<StabilityRow> rows = run_stability(sc, o);
  std::cout << "engine,integrator,stable_dt,first_unstable_dt,predicted_dt,ratio\n";
  for (const StabilityRow& r : rows) {
    // "none": no stable dt found, or no failure up to --dt-max (the ratio is then left out)
    std::cout << r.engine << ',' << r.integrator << ','
              << (std::isfinite(r.stable_dt) ? format_double(r.stable_dt) : "none") << ','
              << (std::isfinite(r.first_unstable_dt) ? format_double(r.first_unstable_dt) : "none")
              << ',' << (std::isnan(r.predicted_dt) ? "" : format_double(r.predicted_dt)) << ','
              << (std::isfinite(r.ratio) ? format_double(std::round(r.ratio * 1000) / 1000) : "")
              << '\n';
  }
  std::cout << std::flush;
  if (o.progress) std::cerr << "wrote " << o.out_dir << "/stability.csv\n";
  return kOk;
}

int cmd_accuracy(const std::string& path, const std::vector<std::string>& overrides,
                 AccuracyOptions o) {
  const Scenario sc = load(path, overrides, o.engines);
  if (o.out_dir.empty()) o.out_dir = "out/" + sc.name + "-accuracy";
  const AccuracyReport report = run_accuracy(sc, o);
  std::cout << accuracy_summary(report) << std::flush;
  return kOk;
}

// every shipped scenario file, sorted
std::vector<std::string> shipped_scenarios() {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(CLOTHBENCH_SCENARIO_DIR))
    if (e.path().extension() == ".toml") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

int cmd_check(std::vector<std::string> paths, const CheckOptions& o) {
  if (paths.empty()) paths = shipped_scenarios();
  std::vector<Gate> all;
  for (const std::string& p : paths) {
    const std::vector<Gate> g = check_scenario(p, o);
    all.insert(all.end(), g.begin(), g.end());
  }
  const long failed = std::count_if(all.begin(), all.end(), [](const Gate& g) { return !g.pass; });
  if (o.update) {
    std::cout << (all.empty() ? std::string("baselines recorded; nothing changed\n")
                              : "baselines recorded; what changed:\n" + format_gates(all));
    return kOk;
  }
  const long ungated =
      std::count_if(all.begin(), all.end(), [](const Gate& g) { return !g.gated; });
  std::cout << format_gates(all) << long(all.size()) - failed - ungated << " gates passed, "
            << failed << " failed, " << ungated << " not gated\n";
  return failed > 0 ? 1 : kOk;
}

// runs analysis/report.py with Debian's python3 (for its matplotlib); returns its exit code
int cmd_report(const std::vector<std::string>& args) {
  const std::string script = std::string(CLOTHBENCH_ANALYSIS_DIR) + "/report.py";
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
    ::execv(python, argv_c.data());
    std::cerr << "clothbench: cannot run " << python << ": " << std::strerror(errno) << '\n';
    std::_Exit(kBadInput);
  }
  int status = 0;
  if (pid < 0 || ::waitpid(pid, &status, 0) < 0)
    throw std::runtime_error("cannot start " + std::string(python));
  return WIFEXITED(status) ? WEXITSTATUS(status) : kInternal;
}

int cmd_list() {
  std::cout << "scenarios (" << CLOTHBENCH_SCENARIO_DIR << "):\n";
  for (const std::filesystem::path f : shipped_scenarios()) {
    try {
      const Scenario sc = load_scenario(f.string());
      std::cout << "  " << sc.name << "  " << sc.scene.cloth.nu << "x" << sc.scene.cloth.nv << ", "
                << sc.engines.size() << " engines: " << sc.description << '\n';
    } catch (const std::exception& e) {
      std::cout << "  " << f.filename().string() << "  (does not load: " << e.what() << ")\n";
    }
  }
  std::cout << "engine kinds:";
  for (const EngineKindInfo& k : engine_kind_table()) std::cout << ' ' << k.name;
  std::cout << "\nintegrators (kind = \"custom\"):";
  for (cloth::Integrator i : cloth::all_integrators())
    std::cout << ' ' << cloth::integrator_name(i);
  std::cout << '\n';
  return kOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "clothbench: a custom mass-spring cloth and Bullet's soft bodies on identical scenes,\n"
      "with energy, drape-shape and stability differences logged to CSV."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "clothbench 0.1.0");

  std::string scenario_path, out;
  std::vector<std::string> engines, overrides;
  bool quiet = false;
  CLI::App* run = app.add_subcommand(
      "run",
      "Run every engine of a scenario on its scene and write frames, divergence, snapshots "
      "and summary CSVs.\nWithout SCENARIO: the course report's seed scene on several "
      "integrators.");
  run->add_option("scenario", scenario_path,
                  "scenario file (TOML); default: the embedded seed scene");
  run->add_option("--out,-o", out, "output folder (default: out/<scenario name>)");
  run->add_option("--engine,-e", engines,
                  "run only this engine (repeatable; the reference always runs)")
      ->allow_extra_args(false);
  run->add_option(
         "--set,-s", overrides,
         "override a scenario key, e.g. cloth.damping=0 or engine.custom-rk4.dt=2e-4 (repeatable)")
      ->allow_extra_args(false);
  run->add_flag("--quiet,-q", quiet, "no progress on stderr");
  run->footer(
      "Exit status: 0 when every engine ran (an unstable run is a result), 2 for bad input, 1 for "
      "an internal error.");

  StabilityOptions stab;
  CLI::App* stability = app.add_subcommand(
      "stability",
      "Find the largest stable time step of each engine and integrator, measured by search\n"
      "(doubling, then bisection, over steps that divide the run's length) and predicted by\n"
      "linear theory; writes stability.csv, whose rerun columns replay a row with `clothbench\n"
      "run SCENARIO <rerun>`, and stability_scenario.toml, which --resume checks.");
  stability->add_option("scenario", scenario_path,
                        "scenario file (TOML); default: the embedded seed scene");
  stability->add_option("--out,-o", stab.out_dir, "output folder (default: out/<scenario name>)");
  stability->add_option("--engine,-e", stab.engines, "search only this engine (repeatable)")
      ->allow_extra_args(false);
  stability
      ->add_option("--integrator,-i", stab.integrators,
                   "custom engines: only this integrator (repeatable; default: all six)")
      ->allow_extra_args(false);
  stability->add_option("--dt-max", stab.dt_max, "largest dt tried (s)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  stability
      ->add_option("--rel-tol", stab.rel_tol,
                   "bisection stops when first_unstable / stable - 1 <= this (or when they are\n"
                   "one step count apart)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  stability->add_option("--jobs,-j", stab.jobs, "searches run at once (default: all cores)")
      ->check(CLI::PositiveNumber);
  stability->add_flag("--resume", stab.resume,
                      "keep the rows already in stability.csv and search only the rest (refused\n"
                      "when the scenario, --set, --engine, --dt-max or --rel-tol differ)");
  stability->add_option("--set,-s", overrides, "override a scenario key (repeatable)")
      ->allow_extra_args(false);
  stability->add_flag("--quiet,-q", quiet, "no progress on stderr");

  AccuracyOptions acc;
  std::string dts_text, resolutions_text;
  CLI::App* accuracy = app.add_subcommand(
      "accuracy",
      "Error against a fine rk4 reference and cost, over a time-step sweep of every engine and\n"
      "integrator: work_precision.csv, convergence.csv (fitted orders), and with --tolerance the\n"
      "cheapest configuration that meets it (recommendation.csv).");
  accuracy->add_option("scenario", scenario_path,
                       "scenario file (TOML); default: the embedded seed scene");
  accuracy->add_option("--out,-o", acc.out_dir,
                       "output folder (default: out/<scenario name>-accuracy)");
  accuracy->add_option("--engine,-e", acc.engines, "sweep only this engine (repeatable)")
      ->allow_extra_args(false);
  accuracy
      ->add_option("--integrator,-i", acc.integrators,
                   "custom engines: only this integrator (repeatable)")
      ->allow_extra_args(false);
  auto* dts_opt = accuracy->add_option("--dts", dts_text,
                                       "time steps to sweep (s), comma separated, e.g. 1e-4,5e-5");
  accuracy
      ->add_option("--halvings", acc.halvings,
                   "without --dts: this many time steps, halving from each engine's dt")
      ->capture_default_str()
      ->check(CLI::PositiveNumber)
      ->excludes(dts_opt);
  accuracy->add_option(
      "--tolerance", acc.tolerance,
      "error tolerance (m, RMS distance): recommend the cheapest configuration within it.\n"
      "Cheapest is counted, not timed, so it does not change with the machine or --jobs: per\n"
      "engine the fewest force evaluations + 3 x CG iterations (a CG iteration with its share\n"
      "of the Newton linearisation costs about 3 force evaluations), times particles; Bullet\n"
      "engines, whose work is not counted, the fewest steps x particles; ties go to the smaller\n"
      "error. Overall compares the engines' choices by that count when all are custom, and by\n"
      "wall time per simulated second when Bullet is among them (wall time stays in the CSV)");
  accuracy->add_option("--resolutions", resolutions_text,
                       "square grid sizes to compare at each engine's dt, e.g. 9,13,17,25,33");
  accuracy->add_option("--repeats", acc.repeats, "wall time is the median of this many runs")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  accuracy
      ->add_option("--jobs,-j", acc.jobs,
                   "runs at once (default: all cores; timings are cleaner with 1)")
      ->check(CLI::PositiveNumber);
  accuracy->add_flag("--resume", acc.resume,
                     "keep the rows already in the output folder and run only the rest");
  accuracy->add_option("--set,-s", overrides, "override a scenario key (repeatable)")
      ->allow_extra_args(false);
  accuracy->add_flag("--quiet,-q", quiet, "no progress on stderr");

  CheckOptions chk;
  chk.baseline_dir = CLOTHBENCH_BASELINE_DIR;
  std::vector<std::string> check_paths;
  CLI::App* check = app.add_subcommand(
      "check",
      "Rerun scenarios and compare every gated quantity with its recorded baseline (final shape,\n"
      "energy error, stability, divergence from the reference, force evaluations, CG\n"
      "iterations). Exit status 1 when any gate fails. --update records new baselines.");
  check->add_option("scenarios", check_paths, "scenario files (default: every shipped scenario)");
  check
      ->add_option("--baseline,-b", chk.baseline_dir,
                   "baseline folder (one subfolder per scenario)")
      ->capture_default_str();
  check->add_flag("--update", chk.update,
                  "record the current results as the baseline and print what changed "
                  "(metrics, final shape RMS per engine, stability limits)");
  check->add_flag("--record-perturbed", chk.record_perturbed,
                  "let --update record a baseline with --set overrides applied (refused "
                  "without this flag)");
  check->add_option("--set,-s", overrides, "override a scenario key in every scenario (repeatable)")
      ->allow_extra_args(false);
  check->add_option("--jobs,-j", chk.jobs, "threads for the stability searches")
      ->check(CLI::PositiveNumber);
  check->add_flag("--quiet,-q", quiet, "no progress on stderr");

  CLI::App* report = app.add_subcommand(
      "report",
      "Plots and a self-contained report.html from an output folder (runs analysis/report.py\n"
      "with /usr/bin/python3). Everything after `report` goes to the script: DIR\n"
      "[--compare DIR2] [--labels A,B] [--out OUTDIR] [--svg] [--snapshot-times LIST]\n"
      "[--tolerance E]; `clothbench report --help` shows the script's own help.");
  report->set_help_flag();  // --help goes to the script, whose help lists its options
  report->allow_extras();
  report->prefix_command();

  CLI::App* list =
      app.add_subcommand("list", "List the shipped scenarios, engine kinds and integrators.");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kOk : kBadInput;
  }
  std::signal(SIGINT, [](int) { interrupt_requested() = true; });
  std::signal(SIGTERM, [](int) { interrupt_requested() = true; });
  try {
    if (*run) return cmd_run(scenario_path, out, engines, overrides, quiet);
    if (*list) return cmd_list();
    if (*report) return cmd_report(report->remaining());
    if (*check) {
      chk.overrides = overrides;
      chk.progress = !quiet;
      return cmd_check(check_paths, chk);
    }
    if (*accuracy) {
      acc.progress = !quiet;
      acc.dts = parse_list<double>(dts_text, "--dts");
      acc.resolutions = parse_list<int>(resolutions_text, "--resolutions");
      return cmd_accuracy(scenario_path, overrides, acc);
    }
    if (*stability) {
      stab.progress = !quiet;
      return cmd_stability(scenario_path, overrides, stab);
    }
  } catch (const Interrupted&) {
    // a run writes nothing until it is complete; a sweep has kept every finished row
    if (*stability || *accuracy)
      std::cerr << "clothbench: interrupted; the finished rows are kept (--resume goes on)\n";
    else
      std::cerr << "clothbench: interrupted; no output written\n";
    return kInterrupted;
  } catch (const ScenarioError& e) {
    std::cerr << "clothbench: " << e.what() << '\n';
    return kBadInput;
  } catch (const std::invalid_argument& e) {
    std::cerr << "clothbench: " << e.what() << '\n';
    return kBadInput;
  } catch (const std::runtime_error& e) {
    std::cerr << "clothbench: " << e.what() << '\n';
    return kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "clothbench: internal error: " << e.what() << '\n';
    return kInternal;
  }
  return kInternal;
}
