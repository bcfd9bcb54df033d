#pragma once
/// @file stability_sweep.hpp
/// `clothbench stability`: the largest stable time step of each engine and integrator on a
/// scenario, measured by search and predicted by linear theory.
///
/// Every run of a search covers the same horizon, the scenario's duration as `clothbench run`
/// simulates it (a whole number of frame intervals), in a whole number of steps: the time
/// steps tried are horizon / N for integers N. A run is then one frame long, so each verdict
/// can be replayed with `clothbench run` by setting frame_interval to the horizon (which every
/// engine's dt divides, since each divides frame_interval) and dt to horizon / N.
///
/// Files written into StabilityOptions::out_dir:
///   stability.csv             one row per engine and integrator (columns: io/output_schema.cpp,
///                             printed by `clothbench schema --outputs`)
///   stability_scenario.toml   the resolved scenario and the search options (checked by resume)
///   shard.toml                with --shard: which share of the sweep (shard.hpp)

#include <limits>
#include <string>
#include <vector>

#include "harness/run/run_parallel.hpp"
#include "harness/scenario/scenario.hpp"
#include "harness/sweeps/shard.hpp"
#include "harness/sweeps/stability_search.hpp"
#include "harness/sweeps/sweep.hpp"

namespace clothbench {

/// Options of a stability search.
struct StabilityOptions {
  std::string out_dir;                         // stability.csv goes here (created)
  std::vector<std::string> engines;            // engine names; empty: all
  std::vector<cloth::Integrator> integrators;  // custom engines; empty: every integrator
  double dt_max = 0.1;                         // s, no dt above this is tried
  double rel_tol = 0.02;  // bisection until first_unstable / stable - 1 <= this
                          // (or the two are neighbours on the step grid)
  int jobs = default_jobs();
  bool resume = false;
  bool progress = true;
  Shard shard;  // --shard K/N: only this share of the searches (shard.hpp)
};

/// One row of stability.csv.
struct StabilityRow {
  std::string engine, integrator;
  double stable_dt = std::numeric_limits<double>::quiet_NaN();  // s, largest dt found stable
                                                                // over the horizon (NaN: none)
  double first_unstable_dt = std::numeric_limits<double>::infinity();  // s, smallest dt found
                                                                       // unstable above it
                                                                       // (infinity: none up
                                                                       // to dt_max)
  double predicted_dt = std::numeric_limits<double>::quiet_NaN();      // s, linear theory (NaN: no
                                                                       // theory for this engine)
  double ratio = std::numeric_limits<double>::quiet_NaN();  // stable_dt / predicted_dt when
                                                            // both limits were found (NaN when
                                                            // the measurement is only a bound)
  std::string cause;           // how the first unstable run failed, and the limiting mode
  std::string rerun;           // --set overrides that rerun the stable_dt run ("" when none)
  std::string rerun_unstable;  // --set overrides that rerun the first_unstable_dt run
  int runs = 0;                // simulations the search took
  bool resumed = false;        // read back from an earlier sweep's stability.csv (no new runs)
};

/// Finds the limits: from the engine's dt (or dt_max when that is smaller), doubling until a
/// run is unstable (halving up to 10 times first if the engine's own dt is unstable), then
/// bisection on a log scale to rel_tol. Throws UserError for bad options (an unknown engine),
/// an unwritable out_dir, a malformed stability.csv to resume, or a resume against a sweep of
/// another scenario or other options.
std::vector<StabilityRow> run_stability(const Scenario& sc, const StabilityOptions& o);

}  // namespace clothbench
