#pragma once
/// @file mesh_check.hpp
/// What makes a triangle mesh unusable as a cloth, found in O(#V + #T log #T) time (sorting,
/// no pairwise loops): bad coordinates or indices, zero-area triangles, edges of more than two
/// triangles, vertices where two fans meet (bowties), orientation flipped across an edge, and
/// (a warning only) vertices in no triangle.

#include <string>
#include <vector>

#include "cloth/model/triangle_mesh.hpp"

namespace cloth {

/// The kinds of problem, in the order check_mesh reports them.
enum class MeshProblemKind {
  non_finite_vertex,         ///< a coordinate is NaN or infinite (vertex)
  index_out_of_range,        ///< a triangle names a vertex outside [0, #V) (triangle)
  degenerate_triangle,       ///< a repeated vertex or (near) zero area (triangle)
  oversized_triangle,        ///< a side whose squared length overflows a double (triangle)
  non_manifold_edge,         ///< an edge shared by more than two triangles (triangle: the third)
  inconsistent_orientation,  ///< two triangles run along their shared edge the same way
                             ///< (triangle: the later one)
  bowtie_vertex,             ///< the triangles around a vertex form two or more fans (vertex)
  unused_vertex              ///< a vertex in no triangle (vertex); a warning, not an error
};

/// One problem of a mesh.
struct MeshProblem {
  MeshProblemKind kind = MeshProblemKind::degenerate_triangle;
  int vertex = -1;          ///< the vertex concerned, or the edge's first vertex; -1: none
  int other_vertex = -1;    ///< the edge's second vertex (edge problems); -1: none
  int triangle = -1;        ///< the triangle concerned; -1: none
  int other_triangle = -1;  ///< the first of the two disagreeing triangles
                            ///< (inconsistent_orientation); -1: none
  std::string message;      ///< what is wrong, in words, with 0-based indices

  /// False for a warning (unused_vertex): the mesh is still usable.
  bool is_error() const { return kind != MeshProblemKind::unused_vertex; }
};

/// A triangle is degenerate when its area is at most this fraction of its longest edge
/// squared (its height below 2e-12 of that edge): zero area up to round-off.
constexpr double kDegenerateAreaRatio = 1e-12;

/// Every problem of mesh, errors by kind (in enum order) then index, warnings last. A triangle
/// with an index out of range is left out of the later checks.
std::vector<MeshProblem> check_mesh(const TriangleMesh& mesh);

/// The number of problems in problems that are errors.
int error_count(const std::vector<MeshProblem>& problems);

}  // namespace cloth
