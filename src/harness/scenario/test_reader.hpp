#pragma once
/// @file test_reader.hpp
/// Reads a scenario's [test] table: which textile standard test the harness measures on every
/// engine's final state, checked against the scene it measures.

#include <toml++/toml.h>

#include "harness/scenario/scenario.hpp"
#include "harness/scenario/toml_reader.hpp"

namespace clothbench {

/// Fills s.test from root's [test] (nothing when there is none); s.scene (its constraints
/// included) must be read already. kind = "cantilever" needs a particle at rest x <= edge, one
/// beyond it, every particle at rest x <= edge held on all axes, and a non-zero gravity;
/// "bias-extension" a generated rectangle with lattice = "grid" at 45 degrees at least twice
/// as long (x) as wide, a clamp held on all axes and one handle pulling along +x beyond it.
/// Throws ScenarioError naming the key otherwise.
void read_test(const Reader& r, const toml::table& root, Scenario& s);

}  // namespace clothbench
