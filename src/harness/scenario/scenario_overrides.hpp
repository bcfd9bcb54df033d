#pragma once
/// @file scenario_overrides.hpp
/// --set KEY=VALUE overrides applied to a parsed scenario file before it is read, and an
/// [[engine]]'s own: `overrides = { "cloth.stiffness.bend" = 3.2 }`, the same key paths
/// applied to the scenario for that engine alone, so that it runs a scene that differs from the
/// others' only by those keys (what `clothbench fit` writes).

#include <toml++/toml.h>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "harness/scenario/scenario.hpp"
#include "harness/scenario/toml_reader.hpp"

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

/// The top-level keys an engine's overrides may address: the scene's physics (the cloth, gravity,
/// wind and the colliders), not run settings, constraints, handles, the [test] or engines.
extern const Keys kEngineOverrideTops;

/// Reads the overrides table of every engine that has one: engines[k] is the [[engine]] table
/// of s.engines[k]. Fills EngineSpec::overrides and EngineSpec::scene; read reads a whole
/// scenario from a table (the loader's own reader) and is given root with the engine's
/// overrides applied, the engine alone and no reference. Throws ScenarioError naming the file,
/// engine.NAME.overrides and the key: an override of an engine key or a run setting, an
/// unknown key, a value the key refuses, and overrides that change the cloth's rest shape or
/// its held particles.
void read_engine_overrides(const Reader& r, const toml::table& root,
                           const std::vector<const toml::table*>& engines, Scenario& s,
                           const std::function<Scenario(const toml::table&)>& read);

/// A value of an overrides table as TOML text (numbers, strings, booleans and arrays of them);
/// nullopt for a table or a date.
std::optional<std::string> override_value_text(const toml::node& n);

}  // namespace clothbench
