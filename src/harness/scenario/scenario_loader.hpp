#pragma once
/// @file scenario_loader.hpp
/// Scenario files (TOML) to Scenario, with strict validation, --set overrides and the way back.
///
/// Every error a user can cause is a ScenarioError whose message names where (file and line,
/// or the --set override), the key, and what was expected:
///   scenarios/x.toml:12: cloth.damping: expected a number >= 0, got -3
///   --set engine.custom-rk4.dt: expected a number > 0, got -1

#include <string>
#include <string_view>
#include <vector>

#include "harness/scenario/scenario.hpp"
#include "harness/scenario/scenario_error.hpp"

namespace clothbench {

/// Reads, overrides and validates the scenario file at path; source is set to path.
/// @param overrides  "key=value" strings as given to --set, applied in order before validation
/// @param only  engine names to keep (the reference is always kept); empty keeps every engine.
///               Only kept engines must be able to model the scene.
/// Throws ScenarioError for an unreadable file or anything parse_scenario rejects.
Scenario load_scenario(const std::string& path, const std::vector<std::string>& overrides = {},
                       const std::vector<std::string>& only = {});

/// Parses, overrides and validates scenario text; source_name stands for the file in messages.
///
/// Overrides address keys by dotted path: "duration=0.5", "cloth.damping=0",
/// "cloth.particles=[9,9]", "cloth.stiffness.shear=0", "sphere.0.radius=0.5",
/// "constraint.0.hold=y", "engine.custom-rk4.dt=2e-4" (an engine by name, or by index).
/// The value is a TOML value; a bare word (=xy) is a string. Setting particle_mass removes
/// total_mass and vice versa; setting a stiffness kind when the file has no stiffness table
/// starts from the default table. Throws ScenarioError.
Scenario parse_scenario(std::string_view toml_text, const std::string& source_name,
                        const std::vector<std::string>& overrides = {},
                        const std::vector<std::string>& only = {});

/// The text of scenarios/seed_sphere_drape.toml, compiled into the binary.
std::string embedded_default_scenario();

}  // namespace clothbench
