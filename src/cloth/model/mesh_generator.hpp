#pragma once
/// @file mesh_generator.hpp
/// Triangle meshes of simple shapes, made by the tool itself: a Delaunay triangulation (Qhull)
/// of a jittered point set, rings for a disk or an annulus, a triangular lattice for a
/// rectangle or a tube; points on the boundary lie exactly on it, triangles in the annulus'
/// hole are removed, and every triangle is oriented the same way. A rectangle may instead be a
/// square grid of yarns at an angle (lattice = grid): see MeshLattice::grid.
///
/// The same spec gives the same mesh, bit for bit, on every machine: the jitter comes from
/// splitmix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number generators",
/// OOPSLA 2014) seeded with spec.seed, each 64-bit output u mapped to [0, 1) as
/// (u >> 11) * 2^-53; angles use this file's own sine and cosine polynomials, not the C
/// library's; the file is compiled with -ffp-contract=off so that no fused multiply-add can
/// change a rounding; and the triangles are put in a canonical order (each rotated to start at
/// its smallest index, then sorted), whatever order Qhull returns them in. Points in general
/// position have one Delaunay triangulation, so Qhull's version does not matter either.

#include <cstdint>
#include <string>
#include <vector>

#include "cloth/model/scene.hpp"
#include "cloth/model/triangle_mesh.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// The shapes generate_mesh makes.
enum class MeshShape {
  disk,       ///< a disk of radius, in plane
  annulus,    ///< a disk of radius with a hole of inner_radius, in plane
  rectangle,  ///< size_u by size_v, in plane (u along x, v along z for xz or y for xy)
  tube        ///< a cylinder surface, axis along y, of radius and length, open at both ends
};

/// How a rectangle is filled.
enum class MeshLattice {
  triangular,  ///< a jittered triangular lattice, Delaunay-triangulated
  /// a square grid (yarns) at lattice_angle to u, each square split into two triangles (at 45
  /// degrees along its diagonal along u); the angle a multiple of 45 degrees, so that the
  /// rectangle's edges run along yarns (0, 90) or along the squares' diagonals (45, 135), where the
  /// squares the edge cuts in half leave triangles; the mesh's cells list the squares
  grid
};

/// The lattice's name in scenario files: "triangular", "grid".
const char* mesh_lattice_name(MeshLattice lattice);

/// The shape's name in scenario files: "disk", "annulus", "rectangle", "tube".
const char* mesh_shape_name(MeshShape shape);
/// Every shape, in the order of the enum.
const std::vector<MeshShape>& all_mesh_shapes();

/// What generate_mesh makes.
struct ShapeSpec {
  MeshShape shape = MeshShape::disk;
  double radius = 0.15;                           // m, disk, annulus (outer), tube
  double inner_radius = 0.05;                     // m, annulus
  double size_u = 1.0;                            // m, rectangle
  double size_v = 1.0;                            // m, rectangle
  double length = 0.4;                            // m, tube
  double edge_length = 0.01;                      // m, the target length of an edge
  std::uint64_t seed = 1;                         // the jitter's seed
  Vector3 center = {0.0, 1.0, 0.0};               // m, the shape's centre
  Plane plane = Plane::xz;                        // disk, annulus, rectangle
  MeshLattice lattice = MeshLattice::triangular;  // rectangle
  double lattice_angle = 0.0;                     // degrees, grid: the yarns' angle to u
};

/// The most vertices generate_mesh makes (the OBJ reader's limit too).
constexpr int kMaxGeneratedVertices = 2000000;

/// Why spec cannot be generated ("radius: expected a number > 0", a mesh over
/// kMaxGeneratedVertices, an annulus narrower than an edge, a tube less than six edges around),
/// as "KEY: what is expected", or "" when it can.
std::string shape_spec_problem(const ShapeSpec& spec);

/// The mesh of spec: vertices in generation order (rings from the inside out, lattice rows
/// from v = -size_v/2 or y = -length/2 up), triangles in canonical order, no groups. Planar
/// shapes face +y (xz) or +z (xy); a tube's normals point out of its axis. Passes check_mesh
/// with no problem at all. A grid lattice's spacing is edge_length rounded per axis so that
/// the rectangle holds whole steps (at 45 degrees an even number of half-diagonals h / sqrt(2)
/// along u and along v): its squares are exact when size_u and size_v are whole multiples of
/// the step, else slightly rhombic. Its vertices go row by row from v = -size_v/2 up, and
/// mesh.cells lists its squares (and half squares) for springs along yarns and diagonals.
/// Throws std::invalid_argument when shape_spec_problem(spec) is not
/// empty.
TriangleMesh generate_mesh(const ShapeSpec& spec);

}  // namespace cloth
