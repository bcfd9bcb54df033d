#pragma once
/// @file welch_test.hpp
/// Welch's two-sample t-test: whether two ensembles of one quantity have the same mean,
/// without assuming equal variances, and the Student t distribution's tail it needs
/// (through the regularized incomplete beta function).

#include <vector>

namespace clothbench {

/// The regularized incomplete beta function I_x(a, b) for a, b > 0 and x in [0, 1], by the
/// continued fraction (modified Lentz), to about 1e-14 relative.
double regularized_incomplete_beta(double a, double b, double x);

/// Two-sided tail of Student's t distribution with dof > 0 degrees of freedom (dof need not
/// be whole): P(|T| >= |t|) = I_{dof / (dof + t^2)}(dof / 2, 1 / 2).
double student_t_two_sided(double t, double dof);

/// The mean and the sample standard deviation (n - 1) of v (at least 2 values), in v's unit.
void sample_moments(const std::vector<double>& v, double& mean, double& sd);

/// What Welch's test says of two samples a and b.
struct WelchResult {
  double mean_a = 0, mean_b = 0;  // sample means, in the quantity's unit
  double sd_a = 0, sd_b = 0;      // sample standard deviations (n - 1), same unit
  double t = 0;                   // (mean_b - mean_a) / sqrt(var_a / n_a + var_b / n_b)
  double dof = 0;                 // Welch-Satterthwaite degrees of freedom
  double p = 1;                   // two-sided p-value of t
};

/// Welch's t-test of a against b (each at least 2 values, all finite; else p is NaN). Both
/// spreads zero: p = 1 for equal means and 0 otherwise.
WelchResult welch_test(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace clothbench
