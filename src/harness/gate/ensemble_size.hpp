#pragma once
/// @file ensemble_size.hpp
/// How large an ensemble must be (tolerances_file.hpp, [ensemble.<engine>] with `detect`): the
/// smallest shift of a quantity's mean that the ensemble gate catches, and the number of
/// members that brings that shift down to a stated goal.
///
/// The gate is Welch's two-sided test at false-alarm rate alpha between two ensembles of N
/// members each (ensemble_gate.hpp). Its power against a true shift d of the mean is computed
/// for normal members whose spread sd is the same on both sides, the spread the recorded
/// members measure. With equal sides, Welch's statistic is (Z + lambda) / sqrt(W / (2N - 2))
/// with Z standard normal, lambda = d / (sd sqrt(2 / N)) and W chi-square with 2N - 2 degrees
/// of freedom, and its degrees of freedom are (N - 1) / (r^2 + (1 - r)^2) with r, the first
/// side's share of W, Beta((N - 1) / 2, (N - 1) / 2) and independent of W. The power is that
/// double integral, by quadrature: within 1e-7 of the same with four times the nodes (2e-5 at
/// N = 2), where the textbook pooled-t sizing overstates Welch's power (0.90 where it is 0.72
/// at N = 4, alpha = 1e-3).

namespace clothbench {

/// Probability with which the ensemble gate is asked to catch a stated shift.
constexpr double kEnsemblePower = 0.9;

/// Power of Welch's two-sided test at level alpha, two ensembles of n >= 2 members each, with
/// normal members of equal spread, against a shift of the mean of `shift_over_sd` spreads.
double welch_power(double shift_over_sd, int n, double alpha);

/// Smallest shift of the mean (in sd's unit) that Welch's test between two ensembles of n
/// members catches with probability `power` at level alpha: 0 for sd == 0, NaN for a spread
/// that is not a finite number >= 0 or n < 2.
double detectable_shift(double sd, int n, double alpha, double power = kEnsemblePower);

/// Smallest n in [n_min, n_max] with detectable_shift(sd, n, alpha, power) <= shift, or 0
/// when none reaches it (n_min is raised to 2).
int members_needed(double sd, double shift, double alpha, int n_min, int n_max,
                   double power = kEnsemblePower);

}  // namespace clothbench
