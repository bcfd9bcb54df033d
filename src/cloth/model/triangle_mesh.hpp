#pragma once
/// @file triangle_mesh.hpp
/// A cloth given as a triangle mesh (read from an OBJ file or generated): rest positions,
/// triangles, named vertex groups, and what the engines derive from it (edges, bend pairs,
/// lumped masses).

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "cloth/model/types.hpp"

namespace cloth {

/// A triangle mesh in its file's order. A mesh may hold several pieces (disconnected parts).
struct TriangleMesh {
  Matrix3X x;                                 ///< 3 by #V rest positions (m), file order
  std::vector<std::array<int, 3>> triangles;  ///< #T vertex indices (0-based), file order
  std::vector<std::pair<std::string, std::vector<int>>> groups;  ///< named vertex groups
                                                                 ///< (OBJ g/o), sorted indices
  /// a generated grid lattice's squares (MeshLattice::grid): four corners in cyclic order,
  /// -1 for a corner the rectangle's edge cuts off (a half square); empty for other meshes,
  /// whose springs follow their edges
  std::vector<std::array<int, 4>> cells;

  /// Number of vertices (#V).
  int vertex_count() const { return static_cast<int>(x.cols()); }
  /// Number of triangles (#T).
  int triangle_count() const { return static_cast<int>(triangles.size()); }
};

/// The springs' support of a mesh: its edges and, per interior edge, the two vertices
/// opposite it (the ends of its bend spring).
struct MeshEdges {
  std::vector<std::array<int, 2>> edges;       ///< #E unique edges (a, b), a < b, sorted
  std::vector<std::array<int, 2>> bend_pairs;  ///< per edge shared by exactly two triangles,
                                               ///< in edge order: the vertex opposite it in
                                               ///< the lower-numbered triangle, then the other
};

/// The edges and bend pairs of mesh, in a deterministic order (edges sorted by (a, b)).
/// Edges of more than two triangles (refused by check_mesh) get no bend pair.
MeshEdges mesh_edges(const TriangleMesh& mesh);

/// The springs' support of a grid lattice (mesh.cells), like a grid's: pairs (a, b), a < b,
/// sorted, each once.
struct LatticeLinks {
  std::vector<std::array<int, 2>> structural;  ///< the squares' sides (along the yarns)
  std::vector<std::array<int, 2>> shear;       ///< both diagonals of each square (one of a half)
  std::vector<std::array<int, 2>> bend;        ///< particles two sides apart along a yarn
};

/// The lattice links of mesh.cells (all empty when it has none). A bend pair is two sides of
/// one vertex pointing opposite ways at rest (cosine below -0.99), so it follows the yarn.
LatticeLinks lattice_links(const TriangleMesh& mesh);

/// #V lumped masses (kg): a third of each triangle's area times areal_density (kg/m^2) to
/// each of its three vertices; a vertex in no triangle gets 0.
VectorX lumped_masses(const TriangleMesh& mesh, double areal_density);

/// Area of triangle t at the rest positions (m^2).
double triangle_area(const TriangleMesh& mesh, int t);

/// Total area of all triangles at the rest positions (m^2).
double mesh_area(const TriangleMesh& mesh);

}  // namespace cloth
