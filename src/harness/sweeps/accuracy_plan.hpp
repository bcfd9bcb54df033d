#pragma once
/// @file accuracy_plan.hpp
/// What an accuracy sweep will run, decided before anything runs: the configurations of both
/// studies in their file order, the references and the grids of the resolution study.

#include <optional>
#include <string>
#include <vector>

#include "harness/scenario/scenario.hpp"
#include "harness/sweeps/accuracy_rows.hpp"
#include "harness/sweeps/accuracy_sweep.hpp"

namespace clothbench {

/// One configuration to run: an engine of a scenario with its integrator and dt set.
struct AccuracyConfig {
  EngineSpec spec;
  std::optional<cloth::Integrator> integrator;  // none for Bullet engines
  int grid = -1;      // resolution study: index into the grids; -1: time-step study
  std::string key;    // row key in its table
  std::string rerun;  // --set overrides that rerun it
};

/// A reference run: rk4 on the custom engine's options, and how to rerun it.
struct ReferenceRun {
  EngineSpec spec;
  std::string rerun;  // "" when the scenario has no custom engine
};

/// Everything an accuracy sweep runs, in file order.
struct AccuracyPlan {
  std::vector<AccuracyConfig> configs;     // time-step study, then resolution study
  std::vector<std::string> dt_keys;        // work_precision.csv rows, in order
  std::vector<std::string> res_keys;       // resolution.csv rows, in order
  std::vector<std::string> engine_names;   // selected engines, in scenario order
  AccuracyReference reference;             // the time-step study's
  AccuracyReference resolution_reference;  // study "" when there is no resolution study
  ReferenceRun reference_run, floor_run, resolution_reference_run;
  std::vector<Scenario> grids;  // the scene on each grid of the resolution study
  std::vector<int> sizes;       // their sizes r (r x r), from the coarsest
};

/// Checks the options against sc and plans the sweep. Throws UserError for an option a user
/// got wrong (std::invalid_argument for a dt that does not divide frame_interval) and for a
/// scene a selected engine refuses.
AccuracyPlan plan_accuracy(const Scenario& sc, const AccuracyOptions& o);

}  // namespace clothbench
