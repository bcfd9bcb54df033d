#pragma once
/// @file stability_sweep.hpp
/// `clothbench stability`: the largest stable time step of each engine and integrator on a
/// scenario, measured by search and predicted by linear theory.

#include <string>
#include <vector>

#include "harness/scenario.hpp"
#include "harness/sweep.hpp"

namespace clothbench {

/// Options of a stability search.
struct StabilityOptions {
  std::string out_dir;                   // stability.csv goes here (created)
  std::vector<std::string> engines;      // engine names; empty: all
  std::vector<std::string> integrators;  // custom engines; empty: every integrator
  double dt_max = 0.1;                   // s, the scan stops here (implicit methods reach it)
  double rel_tol = 0.02;                 // bisection until first_unstable / stable - 1 <= this
  int jobs = default_jobs();
  bool resume = false;
  bool progress = true;
};

/// One row of stability.csv.
struct StabilityRow {
  std::string engine, integrator;
  double stable_dt = 0;          // s, largest dt found stable over the duration
  double first_unstable_dt = 0;  // s, smallest dt found unstable (infinity: none up to dt_max)
  double predicted_dt = 0;       // s, linear theory (NaN: no theory for this engine)
  std::string cause;             // how the first unstable run failed, and the limiting mode
  std::string rerun;             // --set overrides that rerun the stable_dt row
  int runs = 0;                  // simulations the search took
};

/// Finds the limits: from the engine's dt, doubling until a run is unstable (halving first
/// if the engine's own dt is unstable), then bisection on a log scale to rel_tol.
std::vector<StabilityRow> run_stability(const Scenario& sc, const StabilityOptions& o);

/// Whether one run of engine e over the scenario's duration stays stable; cause says how it
/// failed ("non-finite" or "strain").
bool stable_run(const Scenario& sc, const EngineSpec& e, std::string* cause);

}  // namespace clothbench
