#pragma once
/// @file summaries.hpp
/// The summary tables the commands print on stdout. The harness formats every summary (these
/// two, accuracy_summary beside the accuracy sweep and format_gates beside the gate); the
/// command line only prints them.

#include <string>
#include <vector>

#include "harness/runner.hpp"
#include "harness/stability_sweep.hpp"

namespace clothbench {

/// `clothbench run`: per engine its integrator (or kind), dt, whether it stayed stable, cost
/// per step, largest energy error and final RMS distance from the reference.
std::string run_summary(const RunResult& result);

/// `clothbench stability`: per engine and integrator the searched and predicted limits;
/// "none" where no stable dt was found or nothing failed up to --dt-max.
std::string stability_summary(const std::vector<StabilityRow>& rows);

}  // namespace clothbench
