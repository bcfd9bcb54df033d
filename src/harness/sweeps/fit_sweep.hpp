#pragma once
/// @file fit_sweep.hpp
/// clothbench fit: for each engine, the scene parameters (or the engine's own) that make its
/// metrics hit their targets, one parameter per target metric, over runs of the scenario whose
/// [test] gives the metric: one target by the monotone solver (fit_solver.hpp), several on one
/// engine together by the joint solver (fit_joint.hpp). A target the scenario cannot show at
/// any parameter (fit_reach.hpp) is unreachable before any run.

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "harness/io/fabric_table.hpp"
#include "harness/scenario/scenario.hpp"
#include "harness/sweeps/fit_solver.hpp"

namespace clothbench {

/// One target: a metric by name (a [test] metric or drape_coefficient) and the value wanted.
struct FitTarget {
  std::string metric;
  double value = 0.0;
};

/// A parameter and its range, from --range KEY=LO:HI.
struct FitRange {
  std::string key;  // as --set takes it; engine.KEY for the engine's own key; a+b sets both
  double lo = 0.0;
  double hi = 0.0;
};

/// What to fit.
struct FitOptions {
  std::vector<std::string> scenarios;  // scenario files
  std::vector<FitTarget> targets;
  std::vector<FitRange> ranges;        // the k-th names (and bounds) the k-th target's parameter
  std::vector<std::string> engines;    // engine names; empty: every engine of the scenarios
  std::vector<std::string> overrides;  // --set KEY=VALUE, applied to every scenario
  std::string fabric;       // a preset of reference/fabrics/fabrics.toml: cloth.fabric of every
                            // scenario, and a target for each metric the fabric has a value of
                            // (fabric_targets) that targets does not name
  int max_runs = 12;        // per engine and target (a joint fit: evaluations)
  double tolerance = 0.03;  // relative; drape_coefficient: kDrapeTolerance, absolute
  bool progress = true;     // a line per run on stderr
};

/// The absolute tolerance of drape_coefficient (a fraction itself): the 0.03.
inline constexpr double kDrapeTolerance = 0.03;

/// One row of fit.csv.
struct FitRow {
  std::string engine, parameter;
  double value = 0.0;
  std::string metric;
  double target = 0.0, achieved = 0.0;  // achieved NaN: no run gave the metric
  int runs = 0;
  double sensitivity = 0.0;   // d metric / d parameter, NaN when unmeasured
  std::string sensitivities;  // a joint fit's d metric / d each of its parameters, as
                              // "KEY=VALUE KEY=VALUE"; empty for a one-parameter fit
  std::string status;         // fit_status_name(), or "no engine"
  std::string note;           // why it stopped, for the terminal
  size_t scenario = 0;        // index into FitOptions::scenarios
};

/// Everything a fit found.
struct FitOutcome {
  std::vector<FitRow> rows;
  // per engine, the fitted (key, value) pairs in the order fitted
  std::map<std::string, std::vector<std::pair<std::string, double>>> fitted;
};

/// The parameter fitted for metric on engine e of s when no --range names one:
/// bending_length (and its peirce variant, flexural_rigidity, drape_coefficient) ->
/// cloth.stiffness.bend, or cloth.bending_rigidity for the hinge model; tensile_stiffness ->
/// cloth.stiffness.structural (with the shear springs too on bullet-deformable, which takes one
/// stiffness for both; structural_u or structural_v, the strip's direction, on a grid with
/// per-direction springs); bullet-softbody with stiffness = "klst" -> its own engine.klst.
/// Throws UserError for a metric without a default parameter.
std::string default_parameter(const std::string& metric, const EngineSpec& e, const Scenario& s);

/// The targets fabric f gives the metrics of scenario s: bending_length c = (B / (rho_A g))^(1/3)
/// from its warp rigidity (the cantilever strip lies along u, the warp), tensile_stiffness
/// from its warp or weft tensile stiffness (the strip's direction), drape_coefficient as
/// measured; none for what f lacks.
std::vector<FitTarget> fabric_targets(const Fabric& f, const Scenario& s);

/// Fits every engine to every target (see the file comment). Throws UserError (ScenarioError)
/// for a scenario that does not load, a target no scenario gives, an engine no scenario has.
FitOutcome run_fit(const FitOptions& o);

/// The text of scenario file path with o's --set overrides applied and each engine's fitted
/// values: scene keys as its `overrides = { ... }`, engine keys in its own table. A relative
/// cloth.mesh is made absolute, so that the file reads from any folder.
std::string fitted_scenario_text(const std::string& path, const FitOptions& o,
                                 const FitOutcome& outcome);

/// Writes fit.csv and fitted/<each scenario's file name> into dir (created), all at once.
void write_fit(const FitOptions& o, const FitOutcome& outcome, const std::string& dir);

}  // namespace clothbench
