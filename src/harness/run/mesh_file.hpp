#pragma once
/// @file mesh_file.hpp
/// mesh.obj of a run folder: a mesh cloth's rest shape and triangles, in the order of every
/// other output (the file's order), so the report can draw shapes from snapshots.csv.

#include <string>

#include "cloth/model/model.hpp"

namespace clothbench {

/// The OBJ text of model's rest positions (v, shortest round-trip decimals, m) and triangles
/// (f, 1-based), a comment line first.
std::string rest_mesh_obj(const cloth::Model& model);

}  // namespace clothbench
