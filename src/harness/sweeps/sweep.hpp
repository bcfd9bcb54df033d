#pragma once
/// @file sweep.hpp
/// One configuration of a sweep: an engine of a scenario with its integrator and dt replaced,
/// and the command-line overrides that repeat it with `clothbench run`.

#include <string>

#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// One custom-engine configuration of a sweep: the engine of a scenario with its integrator
/// (custom engines only) and dt replaced.
EngineSpec with_integrator_and_dt(const EngineSpec& e, const std::string& integrator, double dt);

/// The --set overrides that make `clothbench run` repeat a sweep row on the scenario file.
std::string rerun_overrides(const EngineSpec& e);

}  // namespace clothbench
