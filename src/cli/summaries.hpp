#pragma once
/// @file summaries.hpp
/// The summary tables the commands print on stdout (CSV with a header line). The command line
/// is the one place that formats them; accuracy_summary (harness/accuracy_sweep) and
/// format_gates (harness/regression_check) are still to move here.

#include <string>
#include <vector>

#include "harness/runner.hpp"
#include "harness/stability_sweep.hpp"

namespace clothbench::cli {

/// `clothbench run`: per engine its integrator (or kind), dt, whether it stayed stable, cost
/// per step, largest energy error and final RMS distance from the reference.
std::string run_summary(const RunResult& result);

/// `clothbench stability`: per engine and integrator the searched and predicted limits;
/// "none" where no stable dt was found or nothing failed up to --dt-max.
std::string stability_summary(const std::vector<StabilityRow>& rows);

}  // namespace clothbench::cli
