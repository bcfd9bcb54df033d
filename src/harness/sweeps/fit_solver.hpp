#pragma once
/// @file fit_solver.hpp
/// The one-parameter solver of clothbench fit: the positive parameter p at which a monotone
/// metric m(p), measured by a run each time, hits a target. Works in log p: grows a bracket
/// geometrically from the start (secant-guided once two runs give a slope), then closes it by
/// the Illinois variant of regula falsi. Runs that give no metric (a blow-up) bound the range.

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace clothbench {

/// What the solver is asked.
struct FitSolverOptions {
  double target = 0.0;      // the metric's target value
  double tolerance = 0.03;  // done once |m - target| <= tolerance (times |target| if relative)
  bool relative = true;     // tolerance relative to |target|, else absolute
  double start = 1.0;       // first parameter tried, > 0
  double lo = 0.0;          // the parameter's range: lo < p <= hi (lo = 0: start / 1e4)
  double hi = std::numeric_limits<double>::infinity();  // (inf: start * 1e4)
  int max_runs = 12;                                    // runs at most
  double first_factor = 4.0;  // the first bracketing step multiplies p by this (or divides)
};

/// One run: the parameter tried and the metric it gave (NaN: no metric, e.g. a blow-up).
struct FitSample {
  double parameter = 0.0;
  double metric = 0.0;
};

/// How a fit ended.
enum class FitStatus {
  converged,    ///< the metric is within tolerance of the target
  unreachable,  ///< the target lies beyond what the parameter's range (or stability) gives
  budget,       ///< max_runs runs without reaching the tolerance
  failed        ///< no run gave the metric
};

/// "converged", "unreachable", "budget" or "failed".
const char* fit_status_name(FitStatus s);

/// What the solver found: the best run (closest to the target) and every run it made.
struct FitResult {
  FitStatus status = FitStatus::failed;
  double parameter = 0.0;          // of the best run
  double metric = 0.0;             // of the best run (NaN when failed)
  double sensitivity = 0.0;        // d metric / d parameter between the two runs nearest the best
                                   // (in log parameter); NaN with fewer than two runs
  std::vector<FitSample> samples;  // in the order run
  std::string note;                // why it stopped, for a person
};

/// Solves metric(p) = o.target for p in (o.lo, o.hi]; metric is called once per run.
FitResult solve_monotone(const std::function<double(double)>& metric, const FitSolverOptions& o);

}  // namespace clothbench
