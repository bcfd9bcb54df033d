#pragma once
/// @file fit_joint.hpp
/// The joint solver of clothbench fit: the #N positive parameters p at which #M metrics m(p),
/// measured together by one evaluation (a run of each scenario involved), hit their targets.
/// A damped Gauss-Newton (Levenberg-Marquardt) in ln p on residuals in units of each target's
/// tolerance (in ln metric for a positive target, where a power law is a straight line). The
/// Jacobian comes from forward differences at the start and Broyden's update from every later
/// evaluation; a stalled step refreshes it by differences once before the solver gives up.
/// Parameters stay within their ranges; an evaluation without every metric (a blow-up) is a
/// rejected step. Stops when every metric is within its tolerance, when the steps stall (the
/// targets cannot all be met: the least-squares compromise is the best), or at the budget.

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "harness/sweeps/fit_solver.hpp"

namespace clothbench {

/// What the joint solver is asked.
struct JointFitOptions {
  Eigen::VectorXd target;          // #M the metrics' targets
  Eigen::VectorXd tolerance;       // #M absolute tolerances, > 0: done when |m - target| <= them
  Eigen::VectorXd start;           // #N first parameters, lo <= start <= hi
  Eigen::VectorXd lo, hi;          // #N the parameters' ranges, 0 < lo < hi < inf
  std::vector<std::string> names;  // #N the parameters' names, for the notes
  int max_runs = 24;               // evaluations at most
  double difference_step = 0.3;    // ln p step of a forward difference (a factor 1.35)
  double max_step = 2.3;           // largest ln p change of one step in any parameter (10x)
};

/// One evaluation: #N parameters tried and the #M metrics they gave (NaN: no metric).
struct JointSample {
  Eigen::VectorXd parameters;
  Eigen::VectorXd metrics;
};

/// What the joint solver found: the best evaluation and every one it made.
struct JointFitResult {
  FitStatus status = FitStatus::failed;
  Eigen::VectorXd parameters;        // #N of the best evaluation: the converged one, else the one
                                     // of least sum of squared residuals
  Eigen::VectorXd metrics;           // #M of the best evaluation (NaN when failed)
  Eigen::MatrixXd sensitivity;       // #M by #N d metric_i / d parameter_j at the best evaluation,
                                     // from the solver's last Jacobian; NaN where unmeasured
  std::vector<JointSample> samples;  // in the order evaluated
  std::string note;                  // why it stopped, for a person
};

/// The metrics of one evaluation: #N parameters in, #M metrics out (NaN where none).
using JointMetrics = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

/// Solves metrics(p) = o.target within o.tolerance for p in [o.lo, o.hi] (see the file
/// comment); metrics is called once per evaluation. Throws std::invalid_argument for options
/// of mismatched sizes or a range that is not 0 < lo < hi < inf.
JointFitResult solve_joint(const JointMetrics& metrics, const JointFitOptions& o);

}  // namespace clothbench
