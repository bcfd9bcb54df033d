#include "harness/stability/stability_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <stdexcept>

#include "cloth/analysis/linear_stability.hpp"
#include "cloth/model/model.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/progress.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/engine_refusal.hpp"
#include "harness/scenario/scenario_format.hpp"
#include "harness/stability/stability_files.hpp"
#include "harness/stability/stability_search.hpp"
#include "harness/sweeps/sweep_table.hpp"

namespace clothbench {

namespace {

/// One search to make: an engine, with its integrator set for custom engines.
struct StabilityConfig {
  EngineSpec engine;
  std::optional<cloth::Integrator> integrator;  // none for Bullet engines
  size_t row = 0;                               // its row in the whole sweep's stability.csv
  std::string key() const { return engine.name + "," + integrator_label(integrator); }
};

/// What every search shares: the step grid dt = horizon / n, no larger than dt_max.
struct StepGrid {
  double horizon = 0;  // s
  long long n_min = 1;
  double dt(long long n) const { return horizon / double(n); }
};

void check_options(const StabilityOptions& o) {
  if (o.out_dir.empty()) throw UserError("stability: no output folder given");
  if (!(o.dt_max > 0)) throw UserError("--dt-max: expected a time step > 0");
  if (!(o.rel_tol > 0)) throw UserError("--rel-tol: expected a number > 0");
  if (!(o.growth_tol > 0)) throw UserError("--growth-tol: expected a rate > 0 (1/s)");
  if (!(o.perturbation >= cloth::kMinPerturbation && o.perturbation <= cloth::kMaxPerturbation))
    throw UserError(
        "--perturbation " + format_double(o.perturbation) + ": " +
        (o.perturbation < cloth::kMinPerturbation ? "below round-off; "
         : o.perturbation > cloth::kMaxPerturbation
             ? "not a small perturbation (the growth measured would be the nonlinear map's); "
             : "") +
        "expected a number from " + format_double(cloth::kMinPerturbation) + " to " +
        format_double(cloth::kMaxPerturbation) +
        " (relative to the state's scale; the default is 1e-7)");
}

/// Throws UserError naming --dt-max when every run would take more than kMaxSteps steps.
void check_step_count(const Scenario& sc, const StabilityOptions& o) {
  const double steps = stability_horizon(sc) / o.dt_max;
  if (!(steps <= kMaxSteps))
    throw UserError("--dt-max " + format_double(o.dt_max) + ": every run would take at least " +
                    format_double(steps) + " steps of the " + format_double(stability_horizon(sc)) +
                    " s horizon, more than " + format_double(kMaxSteps) +
                    "; expected a larger --dt-max");
}

template <class T>
bool selected(const std::vector<T>& chosen, const T& value) {
  return chosen.empty() || std::find(chosen.begin(), chosen.end(), value) != chosen.end();
}

/// The configurations, engine x integrator in scenario and integrator order; throws
/// UserError for an engine name the scenario does not know, or when none is left.
std::vector<StabilityConfig> plan_configs(const Scenario& sc, const StabilityOptions& o) {
  std::vector<StabilityConfig> configs;
  for (const EngineSpec& e : sc.engines) {
    if (!selected(o.engines, e.name)) continue;
    if (e.kind != EngineKind::custom) {
      configs.push_back({e, std::nullopt});
      continue;
    }
    for (cloth::Integrator i : cloth::all_integrators())
      if (selected(o.integrators, i)) configs.push_back({with_integrator_and_dt(e, i, e.dt), i});
  }
  for (const std::string& name : o.engines)
    if (std::none_of(sc.engines.begin(), sc.engines.end(),
                     [&](const EngineSpec& e) { return e.name == name; }))
      throw UserError("--engine " + name + ": no such engine in " + sc.source);
  if (configs.empty()) throw UserError("nothing to sweep: no engine matches");
  for (const StabilityConfig& c : configs)
    require_engine_can_model(c.engine, sc.scene, "");  // refuse bad scenes early
  return configs;
}

/// The shard's share of the configurations (all of them when not sharded), and the record
/// of the whole sweep for shard.toml.
std::vector<StabilityConfig> shard_configs(const std::vector<StabilityConfig>& all,
                                           const Shard& shard, ShardPlan& plan) {
  plan = {"stability", "stability.csv", {kStabilitySidecar}, 2, 2, {}};
  std::vector<StabilityConfig> mine;
  for (size_t i = 0; i < all.size(); ++i) {
    plan.units.push_back(join_fields({all[i].engine.name, integrator_label(all[i].integrator)}, 2));
    if (shard.owns(i)) mine.push_back(all[i]);
    if (shard.owns(i)) mine.back().row = i;
  }
  return mine;
}

/// Creates the folder, refuses to resume another sweep, records this one beside its table;
/// returns the folder with a trailing '/'.
std::string prepare_folder(const Scenario& sc, const StabilityOptions& o, const ShardPlan& plan) {
  make_directories(o.out_dir);
  const std::string dir = o.out_dir + "/";
  if (o.resume) check_stability_resumable(dir, sc, o);
  record_shard(dir, o.shard, plan, o.resume);
  AtomicFile f(dir + kStabilitySidecar);
  f.write(stability_sidecar_text(sc, o));
  f.commit();
  write_run_info(dir);
  return dir;
}

StepGrid step_grid(const Scenario& sc, const StabilityOptions& o) {
  StepGrid g;
  g.horizon = stability_horizon(sc);
  g.n_min = std::max(1LL, static_cast<long long>(std::ceil(g.horizon / o.dt_max * (1 - 1e-12))));
  return g;
}

/// Why the search ended where it did: what failed (or why nothing did), the limiting mode of
/// the theory, and where the search had to start.
std::string cause_of(const StabilityConfig& c, const StabilityBracket& b, const StepGrid& grid,
                     const cloth::LinearSpectrum& spectrum, double predicted_dt, double dt_max,
                     double sc_max_run_seconds) {
  std::string cause;
  if (b.n_stable == 0 && b.unstable_cause == "timeout")
    cause = "timeout at dt = " + format_double(grid.dt(b.n_unstable)) + " s (--max-run-seconds " +
            format_double(sc_max_run_seconds) + " s): no stable dt found";
  else if (b.n_stable == 0)
    cause = b.unstable_cause + " at every dt tried down to " +
            format_double(grid.dt(b.n_unstable)) + " s (the engine's dt / 2^" +
            std::to_string(kMaxHalvings) + "): no stable dt found";
  else if (b.n_unstable == 0)
    cause = "no failure up to --dt-max = " + format_double(dt_max) +
            " s: stable_dt is a lower bound of the limit";
  else
    cause = b.unstable_cause;
  if (c.engine.kind == EngineKind::custom)
    cause += "; limiting mode " +
             cloth::limiting_mode(c.engine.solver.integrator, spectrum, predicted_dt);
  const long long n_engine = std::max(1LL, std::llround(grid.horizon / c.engine.dt));
  if (n_engine < grid.n_min)
    cause += "; the engine's dt " + format_double(c.engine.dt) +
             " s is above --dt-max: the search started at " + format_double(grid.dt(b.n_start)) +
             " s";
  if (c.engine.kind == EngineKind::custom && !spectrum.exact) cause += " (" + spectrum.method + ")";
  return cause;
}

/// The blow-up columns of a finished search: the limits, their reruns, the prediction and the
/// cause.
void measure(const Scenario& sc, const StabilityConfig& c, const StabilityBracket& b,
             const StepGrid& grid, const cloth::LinearSpectrum& spectrum, double dt_max,
             StabilityRow& row) {
  row.runs = b.runs;
  row.blowup_steps = b.steps;
  const auto spec = [&](long long n) {
    return with_integrator_and_dt(c.engine, c.integrator, grid.dt(n));
  };
  if (b.n_stable > 0) row.stable_dt = grid.dt(b.n_stable);
  if (b.n_unstable > 0) row.first_unstable_dt = grid.dt(b.n_unstable);
  if (b.n_stable > 0) row.rerun = stability_rerun(sc, spec(b.n_stable));
  if (b.n_unstable > 0) row.rerun_unstable = stability_rerun(sc, spec(b.n_unstable));
  row.cause = cause_of(c, b, grid, spectrum, row.predicted_dt, dt_max, sc.max_run_seconds);
  // a ratio only between two limits: a bound or a missing measurement gives none
  if (b.n_stable > 0 && b.n_unstable > 0 && std::isfinite(row.predicted_dt))
    row.ratio = row.stable_dt / row.predicted_dt;
}

/// The growth columns: the limit measured by growth from the predicted limit (custom engines
/// with a finite one) or the engine's dt, and its ratio to the prediction.
void measure_growth(const Scenario& sc, const StabilityConfig& c,
                    const std::vector<GrowthState>& states, const StabilityOptions& o,
                    StabilityRow& row) {
  GrowthSearchOptions go;
  go.perturbation = o.perturbation;
  go.growth_tol = o.growth_tol;
  go.rel_tol = o.rel_tol;
  go.dt_max = o.dt_max;
  go.max_seconds = sc.max_run_seconds;
  // a prediction is mostly within a few per cent of the limit: a first step of 5 %; an
  // engine's own dt is no estimate of it: doubling or halving from the start
  const bool predicted = std::isfinite(row.predicted_dt);
  if (predicted) go.first_step = kPredictionFirstStep;
  const double start = predicted ? row.predicted_dt : c.engine.dt;
  row.growth = search_growth_limit(sc, c.engine, states, start, go);
  if (std::isfinite(row.growth.stable_dt) && std::isfinite(row.growth.first_unstable_dt) &&
      std::isfinite(row.predicted_dt))
    row.growth_ratio = row.growth.stable_dt / row.predicted_dt;
}

/// Searches one configuration from the engine's dt (or dt_max when that is smaller).
StabilityBracket search(const Scenario& sc, const StabilityConfig& c, const StepGrid& grid,
                        double rel_tol) {
  const long long n_engine = std::max(1LL, std::llround(grid.horizon / c.engine.dt));
  return search_stability_limit(sc, c.engine, c.integrator, std::max(grid.n_min, n_engine),
                                grid.n_min, rel_tol);
}

/// One configuration's row by the chosen methods; its mode written when growth found one.
StabilityRow measure_config(const Scenario& sc, const StabilityConfig& c, const StepGrid& grid,
                            const cloth::LinearSpectrum& spectrum,
                            const std::vector<GrowthState>& states, const StabilityOptions& o,
                            const std::string& dir) {
  StabilityRow row;
  row.engine = c.engine.name;
  row.integrator = integrator_label(c.integrator);
  row.method = stability_method_name(o.method);
  if (c.engine.kind == EngineKind::custom)
    row.predicted_dt = cloth::predicted_stable_dt(c.engine.solver.integrator, spectrum);
  if (o.method != StabilityMethod::growth)
    measure(sc, c, search(sc, c, grid, o.rel_tol), grid, spectrum, o.dt_max, row);
  if (o.method != StabilityMethod::blowup) {
    measure_growth(sc, c, states, o, row);
    if (row.growth.mode.size() > 0)
      write_mode(dir + kStabilityModes + "/" + std::to_string(c.row) + ".npy", row.growth.mode);
  }
  return row;
}

}  // namespace

const char* stability_method_name(StabilityMethod m) {
  switch (m) {
    case StabilityMethod::blowup:
      return "blowup";
    case StabilityMethod::growth:
      return "growth";
    case StabilityMethod::both:
      return "both";
  }
  return "both";
}

StabilityMethod parse_stability_method(const std::string& name) {
  for (StabilityMethod m :
       {StabilityMethod::blowup, StabilityMethod::growth, StabilityMethod::both})
    if (name == stability_method_name(m)) return m;
  throw UserError("--method " + name + ": expected blowup, growth or both");
}

std::vector<StabilityRow> run_stability(const Scenario& sc, const StabilityOptions& o) {
  // plan: what to search, in which folder, on which step grid
  check_options(o);
  check_step_count(sc, o);
  ShardPlan plan;
  const std::vector<StabilityConfig> configs = shard_configs(plan_configs(sc, o), o.shard, plan);
  const std::string dir = prepare_folder(sc, o, plan);
  SweepTable table(dir + "stability.csv", stability_header(), 2, o.resume);
  const StepGrid grid = step_grid(sc, o);
  const cloth::LinearSpectrum spectrum = cloth::linear_spectrum(cloth::build_model(sc.scene));
  std::vector<GrowthState> states;
  if (o.method != StabilityMethod::blowup) {
    const double rk4_limit = cloth::predicted_stable_dt(cloth::Integrator::rk4, spectrum);
    if (o.progress) {
      const double h = growth_reference_dt(sc, rk4_limit);
      std::cerr << "growth: the reference states (rk4 over " << format_double(kGrowthWindow)
                << " s in " << std::llround(kGrowthWindow / h) << " steps of " << format_double(h)
                << " s)\n";
    }
    std::string warning;
    states = growth_states(sc, rk4_limit, &warning);
    if (!warning.empty()) std::cerr << "growth: " << warning << "\n";
    make_directories(dir + kStabilityModes);
    write_mode(dir + kStabilityModes + "/rest.npy", cloth::build_model(sc.scene).x0);
  }

  // run and measure every search the folder does not hold yet, reporting each row as it ends
  Progress progress(double(configs.size()), "searches", o.progress);
  std::vector<StabilityRow> rows(configs.size());
  run_parallel(static_cast<int>(configs.size()), o.jobs, [&](int index) {
    const StabilityConfig& c = configs[static_cast<size_t>(index)];
    StabilityRow& row = rows[static_cast<size_t>(index)];
    if (const CsvRecord* kept = table.kept(c.key())) {
      row = stability_row(*kept);
      progress.advance(1, c.key() + " (resumed)");
      return;
    }
    row = measure_config(sc, c, grid, spectrum, states, o, dir);
    table.append(stability_fields(row));
    progress.advance(1, c.key());
  });

  // report: the table in the configurations' order
  std::vector<std::string> order;
  for (const StabilityConfig& c : configs) order.push_back(c.key());
  table.finish(order);
  return rows;
}

}  // namespace clothbench
