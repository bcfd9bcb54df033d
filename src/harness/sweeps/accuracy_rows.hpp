#pragma once
/// @file accuracy_rows.hpp
/// What an accuracy sweep measures, as typed rows: each configuration's error and cost, the
/// reference it is measured against, the fitted orders and the recommendations.

#include <limits>
#include <string>
#include <vector>

namespace clothbench {

/// One row of work_precision.csv or resolution.csv, typed.
struct AccuracyRow {
  std::string engine;
  std::string integrator;  // custom engines; "" for Bullet engines
  int particles = 0;       // #P of the grid it ran on
  double dt = 0;           // s
  bool stable = false;
  double error_final = std::numeric_limits<double>::infinity();  // m, RMS distance to the
                                                                 // reference at the final time
  double error_max = std::numeric_limits<double>::infinity();    // m, largest over the logged
                                                                 // frames (time-step sweep)
  double wall_s = 0;            // s in step(), median of the repeats (time-step sweep)
  double wall_s_per_sim_s = 0;  // s of wall time per simulated second
  long long force_evals = 0;
  long long cg_iterations = 0;  // time-step sweep
  std::string rerun;            // --set overrides that rerun the row with `clothbench run`
};

/// The solution errors are measured against.
struct AccuracyReference {
  std::string study;   // "dt" or "resolution"
  std::string engine;  // custom engine whose solver options it uses ("" when the scenario
                       // has none: the default options)
  double dt = 0;       // s, rk4 time step
  int nu = 0, nv = 0;  // grid
  double error_floor = std::numeric_limits<double>::quiet_NaN();  // m, see below; NaN: not
                                                                  // measured
  std::string description;                                        // one line naming it
};

/// Fitted order of one engine/integrator over the time-step sweep.
struct ConvergenceFit {
  std::string engine;
  std::string integrator;                                   // "" for Bullet engines
  double order = std::numeric_limits<double>::quiet_NaN();  // NaN: fewer than 2 points
  int points = 0;  // stable rows with error_final above the reference's error floor
};

/// The cheapest configuration within the tolerance, for one engine or overall.
struct Recommendation {
  std::string scope;   // "engine" or "overall"
  std::string engine;  // scope "engine": the engine; "overall": the winner's ("" when none)
  bool found = false;  // false: no stable row of the scope meets the tolerance
  AccuracyRow row;     // found: the cheapest; otherwise the most accurate stable row (if any)
};

/// Everything run_accuracy measured, in the files' row order.
struct AccuracyReport {
  AccuracyReference reference;
  std::vector<AccuracyRow> rows;  // work_precision.csv
  std::vector<ConvergenceFit> convergence;
  double tolerance = -1;                        // m, as given
  std::vector<Recommendation> recommendations;  // per engine, then overall (tolerance > 0)
  AccuracyReference resolution_reference;       // study empty when no resolutions
  std::vector<AccuracyRow> resolution_rows;     // resolution.csv
  std::vector<Recommendation> resolution_recommendations;  // (resolutions, tolerance > 0)
  int runs = 0;     // configurations run by this call (identical ones once; references not
                    // counted)
  int resumed = 0;  // rows kept from an earlier sweep (resume)
  std::vector<std::string> files;  // paths written
};

}  // namespace clothbench
