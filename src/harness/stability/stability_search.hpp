#pragma once
/// @file stability_search.hpp
/// The search for one configuration's largest stable time step: runs over a fixed horizon in
/// a whole number of steps, doubled from the engine's dt until one fails, then bisected.

#include <optional>
#include <string>

#include "cloth/model/integrator.hpp"
#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// Halvings of the engine's own dt tried before a configuration is declared never stable:
/// each doubles the cost of a run, so ten already cost 2^11 runs at the engine's dt.
constexpr int kMaxHalvings = 10;

/// The length of every search run (s): the scenario's duration rounded to a whole number of
/// frame intervals, as `clothbench run` simulates it.
double stability_horizon(const Scenario& sc);

/// The --set overrides that make `clothbench run` repeat the search run of engine e (its
/// integrator and dt set) on the scenario file sc came from: integrator, dt, frame_interval
/// set to the horizon, and duration and snapshot_interval where they must change with it.
/// e.dt must divide stability_horizon(sc).
std::string stability_rerun(const Scenario& sc, const EngineSpec& e);

/// Whether one run of engine e over the horizon stays stable; cause says how it failed
/// ("non-finite", "strain", or "timeout" after sc.max_run_seconds). Runs llround(horizon /
/// e.dt) steps, fewer when it fails; steps (when given) gains the steps run.
bool stable_run(const Scenario& sc, const EngineSpec& e, std::string* cause,
                long long* steps = nullptr);

/// Where a search ended, on the step grid dt = horizon / n: n_stable steps were stable and
/// n_unstable (< n_stable) steps were not; 0 where none was found.
struct StabilityBracket {
  long long n_stable = 0;
  long long n_unstable = 0;
  long long n_start = 0;       // step count of the first run
  std::string unstable_cause;  // how the n_unstable run failed
  int runs = 0;                // simulations the search took
  long long steps = 0;         // engine steps of all its runs
};

/// Searches the limit of engine (integrator and dt applied per run) from n_start steps:
/// halving n until a run fails or n_min (the --dt-max bound) is reached, or, when n_start
/// fails, doubling n up to kMaxHalvings times (not after a timeout, nor past kMaxSteps); then
/// bisecting on a log scale until the bracket is within rel_tol or neighbours on the grid. Throws
/// Interrupted when asked to stop.
StabilityBracket search_stability_limit(const Scenario& sc, const EngineSpec& engine,
                                        std::optional<cloth::Integrator> integrator,
                                        long long n_start, long long n_min, double rel_tol);

}  // namespace clothbench
