#pragma once
/// @file test_metrics_gate.hpp
/// The gate on a scenario's textile standard test metrics (tests.csv: bending_length,
/// tensile_stiffness, drape_coefficient, folds, ...): each engine's recorded value of each
/// metric (the baseline's tests.csv) against the one measured now, within the tolerance of
/// tolerances.toml's [tests] table.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "harness/gate/regression_check.hpp"
#include "harness/gate/tolerances_file.hpp"
#include "harness/io/csv_writer.hpp"

namespace clothbench {

/// Test metric values by engine, then by metric (NaN where undefined).
using TestValues = std::map<std::string, std::map<std::string, double>>;

/// The gates of scenario's test metrics: for every engine on both sides, every metric on
/// either side. A metric passes when |now - baseline| <= tolerance.allowed(baseline), or when
/// both are NaN (undefined in both); it fails when one side is NaN, when it is on one side
/// only ("not in the baseline", "recorded but not measured"), or when [tests] gives it no
/// tolerance. An engine on one side only fails once, like a missing or extra engine of
/// metrics.csv. Quantities are named "test." + the metric; one that tolerances lists in
/// [ungated.<engine>] (as "test.<metric>") is shown with its reason, not gated; one an
/// [ensemble.<engine>] lists is left to the ensemble's gate when ensembles_ran, else shown
/// (kEnsembleElsewhere), not gated.
std::vector<Gate> gate_test_metrics(const std::string& scenario, const TestValues& baseline,
                                    const TestValues& now, const Tolerances& tolerances,
                                    bool ensembles_ran);

/// Reads a baseline tests.csv (columns engine, metric, value); throws UserError naming the
/// file and line for a malformed file or a row given twice.
TestValues read_test_values(const std::filesystem::path& p);

/// Writes values as a baseline tests.csv's rows.
void write_test_values(const TestValues& values, CsvWriter& out);

}  // namespace clothbench
