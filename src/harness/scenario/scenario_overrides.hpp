#pragma once
/// @file scenario_overrides.hpp
/// --set KEY=VALUE overrides applied to a parsed scenario file before it is read.

#include <toml++/toml.h>
#include <string>

namespace clothbench {

/// Applies one "key=value" override to root; the value's source reads "--set key", so errors
/// found later name the override. Keys address by dotted path: "duration=0.5",
/// "cloth.damping=0", "cloth.particles=[9,9]", "cloth.stiffness.shear=0", "sphere.0.radius=0.5",
/// "constraint.0.hold=y", "engine.custom-rk4.dt=2e-4" (an engine by name, or by index). The
/// value is a TOML value; a bare word (=xy) is a string. Setting particle_mass removes
/// total_mass and vice versa; setting a stiffness kind when the file has no stiffness table
/// starts from the default table. Throws ScenarioError for a malformed override or an unknown
/// key.
void apply_override(toml::table& root, const std::string& text);

/// The message of an error that an override of key gave, told as the option the user really
/// gave (a --vary value, a --resolutions grid): its leading "--set key: " is replaced by
/// option + ": ". Other messages keep their text behind option + ": ".
std::string as_option_error(const std::string& message, const std::string& key,
                            const std::string& option);

}  // namespace clothbench
