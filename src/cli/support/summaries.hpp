#pragma once
/// @file summaries.hpp
/// The summary tables the commands print on stdout: run, stability and map here, beside the
/// commands that print them (accuracy_summary stays beside the accuracy sweep and format_gates
/// beside the gate).

#include <string>
#include <vector>

#include "harness/run/runner.hpp"
#include "harness/stability/stability_map.hpp"
#include "harness/stability/stability_sweep.hpp"

namespace clothbench {

/// `clothbench run`: per engine its integrator (or kind), dt, whether it stayed stable, cost
/// per step, largest energy error and final RMS distance from the reference.
std::string run_summary(const RunResult& result);

/// `clothbench stability`: per engine and integrator the searched and predicted limits;
/// "none" where no stable dt was found or nothing failed up to --dt-max.
std::string stability_summary(const std::vector<StabilityRow>& rows, StabilityMethod method);

/// The map as printed by `clothbench map`: the varied values, engine, integrator, measured
/// and predicted limits and their ratio.
std::string map_summary(const std::vector<VariedKey>& varied, const std::vector<MapRow>& rows,
                        StabilityMethod method);

}  // namespace clothbench
