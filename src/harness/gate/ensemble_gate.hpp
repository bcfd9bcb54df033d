#pragma once
/// @file ensemble_gate.hpp
/// The ensemble gate of a chaotic scene (tolerances_file.hpp, [ensemble.<engine>]): each
/// listed quantity's mean over N members, now against the recorded members, by Welch's t-test
/// (welch_test.hpp), and the finite-time growth exponent that says by measurement how chaotic
/// the scene is.

#include <map>
#include <string>
#include <vector>

#include "cloth/model/types.hpp"
#include "harness/gate/regression_check.hpp"

namespace clothbench {

/// False-alarm rate of one scenario's ensemble gates together: each of its k ensemble rows is
/// tested at kEnsembleFalseAlarm / k (Bonferroni).
constexpr double kEnsembleFalseAlarm = 1e-3;

/// A figure as the ensemble notes print it: 4 significant digits.
std::string note_number(double v);

/// Members' values by "engine/quantity", in member order (member 0 first).
using EnsembleValues = std::map<std::string, std::vector<double>>;

/// The gate of one quantity: passes when Welch's two-sided p of now against base is at least
/// alpha; its note gives both means, the spreads, t, the degrees of freedom and p. Fails, with
/// the reason, when a side has fewer than 2 members or a value that is not finite on one side
/// only (NaN on both sides in every member, an undefined quantity, passes).
Gate ensemble_gate(const std::string& scenario, const std::string& engine,
                   const std::string& quantity, const std::vector<double>& base,
                   const std::vector<double>& now, double alpha);

/// Finite-time growth exponent (1/s) of a perturbation between two runs over time t_end (s):
/// ln(|x_end_b - x_end_a| / |x_start_b - x_start_a|) / t_end, with |.| the Frobenius norm of
/// 3 by #P positions (m). +inf when the runs start equal and end apart, NaN when they never
/// part (or t_end <= 0).
double growth_exponent(const cloth::Matrix3X& x_start_a, const cloth::Matrix3X& x_start_b,
                       const cloth::Matrix3X& x_end_a, const cloth::Matrix3X& x_end_b,
                       double t_end);

/// Reads a baseline's metrics_ensemble.csv (columns: io/output_schema.cpp); throws UserError
/// naming file and line for a malformed one or a member index out of order.
EnsembleValues read_ensemble(const std::string& path);

/// Appends the rows of metrics_ensemble.csv for values to w (engine, quantity, member, value).
void write_ensemble(const EnsembleValues& values, CsvWriter& w);

}  // namespace clothbench
