#pragma once
/// @file selection_reader.hpp
/// The particles a [[constraint]] or a [[handle]] selects. A grid: corners, an edge, a disk in
/// the cloth plane, (i, j) indices; a mesh: a named vertex group, vertex indices; either: the
/// rest positions within a ball or a box.

#include <toml++/toml.h>
#include <string>

#include "harness/scenario/scenario.hpp"
#include "harness/scenario/toml_reader.hpp"

namespace clothbench {

/// Reads the selection keys of table t (dotted path path) on the cloth of scene, checking
/// that they select at least one particle. keys: the keys t may have.
ConstraintSpec read_selection(const Reader& r, const toml::table& t, const std::string& path,
                              const cloth::Scene& scene, const Keys& keys);

}  // namespace clothbench
