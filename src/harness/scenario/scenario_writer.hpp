#pragma once
/// @file scenario_writer.hpp
/// A Scenario back to TOML: the fully resolved file that repeats a run exactly.

#include <string>

#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// The fully resolved scenario (every key, defaults filled in) as TOML; parsing it gives back
/// the same Scenario (source aside). Doubles are written in their shortest exact form.
std::string scenario_to_toml(const Scenario& scenario);

}  // namespace clothbench
