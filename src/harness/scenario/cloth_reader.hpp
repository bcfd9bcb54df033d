#pragma once
/// @file cloth_reader.hpp
/// The [cloth] table: a grid (particles, size, plane), a triangle mesh read from an OBJ file
/// (mesh = "file.obj", relative to the scenario file) or a shape the tool triangulates itself
/// ([cloth.generate]), with the cloth's mass and springs.

#include <toml++/toml.h>

#include "harness/scenario/scenario.hpp"
#include "harness/scenario/toml_reader.hpp"

namespace clothbench {

/// Reads [cloth] (absent: the default grid) into s.scene.cloth, s.scene.mesh and s.mesh;
/// warnings about the mesh (an unused vertex) go to s.warnings. Throws ScenarioError for a bad
/// key and UserError ("file.obj:LINE: ...") for a bad mesh.
void read_cloth(const Reader& r, const toml::table* table, Scenario& s);

}  // namespace clothbench
