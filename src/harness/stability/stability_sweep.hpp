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
/// Two methods, chosen by StabilityOptions::method: "blowup" searches the largest dt whose run
/// over the horizon stays finite and within the strain limit (above); "growth" measures how
/// fast a small perturbation grows at a few reference states, without waiting for a blow-up
/// (growth_search.hpp), so its limit does not depend on the horizon; "both" does both.
///
/// Files written into StabilityOptions::out_dir:
///   stability.csv             one row per engine and integrator (columns: io/output_schema.cpp,
///                             printed by `clothbench schema --outputs`)
///   stability_modes/ROW.npy   growth: the growing mode of row ROW (its index in stability.csv
///                             counting from 0), float32 of shape (3, #P)
///   stability_modes/rest.npy  growth: the cloth's rest positions, the same shape (m), at
///   growth_first_unstable_dt stability_scenario.toml   the resolved scenario and the search
///   options (checked by resume) shard.toml                with --shard: which share of the sweep
///   (shard.hpp)

#include <limits>
#include <string>
#include <vector>

#include "harness/run/run_parallel.hpp"
#include "harness/scenario/scenario.hpp"
#include "harness/stability/growth_search.hpp"
#include "harness/stability/stability_search.hpp"
#include "harness/sweeps/shard.hpp"
#include "harness/sweeps/sweep.hpp"

namespace clothbench {

/// How `clothbench stability` finds a limit.
enum class StabilityMethod { blowup, growth, both };

/// "blowup", "growth" or "both".
const char* stability_method_name(StabilityMethod m);

/// The method of that name; throws UserError for another.
StabilityMethod parse_stability_method(const std::string& name);

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
  StabilityMethod method = StabilityMethod::blowup;  // `clothbench stability`: both
  double perturbation = 1e-7;                        // growth: relative finite-difference size
  double growth_tol = kDefaultGrowthTol;             // growth: 1/s beyond the physical rate
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
  std::string method;          // "blowup", "growth" or "both"
  GrowthLimit growth;          // growth: the limit found (growth_search.hpp)
  double growth_ratio = std::numeric_limits<double>::quiet_NaN();  // growth.stable_dt /
                                                                   // predicted_dt
  long long blowup_steps = 0;  // engine steps the blow-up search took
};

/// Finds the limits: from the engine's dt (or dt_max when that is smaller), doubling until a
/// run is unstable (halving up to 10 times first if the engine's own dt is unstable), then
/// bisection on a log scale to rel_tol. Throws UserError for bad options (an unknown engine),
/// an unwritable out_dir, a malformed stability.csv to resume, or a resume against a sweep of
/// another scenario or other options.
std::vector<StabilityRow> run_stability(const Scenario& sc, const StabilityOptions& o);

}  // namespace clothbench
