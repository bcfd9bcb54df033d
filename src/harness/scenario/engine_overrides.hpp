#pragma once
/// @file engine_overrides.hpp
/// An [[engine]]'s own scene keys: `overrides = { "cloth.stiffness.bend" = 3.2 }`, --set-style
/// key paths applied to the scenario for that engine alone, so that it runs a scene that
/// differs from the others' only by those keys (what `clothbench fit` writes).

#include <toml++/toml.h>
#include <functional>
#include <string>
#include <vector>

#include "harness/scenario/scenario.hpp"
#include "harness/scenario/toml_reader.hpp"

namespace clothbench {

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
