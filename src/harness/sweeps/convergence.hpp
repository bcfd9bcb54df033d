#pragma once
/// @file convergence.hpp
/// The order of convergence of each configuration of a time-step sweep, fitted to its errors.

#include <vector>

#include "harness/sweeps/accuracy_rows.hpp"

namespace clothbench {

/// Least-squares slope of log(error) against log(dt); NaN for fewer than two points.
double fitted_order(const std::vector<double>& dts, const std::vector<double>& errors);

/// Fitted order per engine and integrator (consecutive rows of one configuration), over
/// the stable rows whose error_final is above error_floor (NaN: every stable row).
std::vector<ConvergenceFit> fit_convergence(const std::vector<AccuracyRow>& rows,
                                            double error_floor);

}  // namespace clothbench
