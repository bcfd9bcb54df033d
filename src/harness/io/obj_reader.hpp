#pragma once
/// @file obj_reader.hpp
/// Wavefront OBJ files as cloth meshes, refused with "PATH:LINE: what is wrong" (a UserError)
/// when they cannot be a cloth.
///
/// Read: `v x y z` (metres; a fourth number, the weight, or three more, a colour, are allowed
/// and ignored); `f` with three or more vertex references, each `a`, `a/b`, `a/b/c` or `a//c`
/// (only a, the vertex, is used; counted from 1, or from the end when negative, as in the
/// format), a polygon split as a fan (a, b, c), (a, c, d), ...; `g` and `o` names, which
/// become named vertex groups holding the vertices of the faces that follow them (`o` starts
/// a new object and clears the `g` names; `g` with several names puts the faces in each).
/// Ignored without a word: comments, blank lines, `vt`, `vn`, `s`, `usemtl`, `mtllib`.
/// Ignored with a warning (one per keyword): `vp`, `l`, `p` and the free-form geometry
/// statements (`cstype`, `deg`, `curv`, `surf`, ...), which describe no triangles. Any other
/// keyword is an error: the file is probably not an OBJ file.
///
/// Refused: a missing or unreadable file, a file over the byte limit, more vertices or
/// triangles than the limits, a number that does not parse or is not finite, a face with
/// fewer than three vertices or a vertex reference that is 0 or out of range, no faces at
/// all, and every error of check_mesh (degenerate triangles, edges of more than two
/// triangles, bowties, inconsistent orientation), each named by the line of its face or
/// vertex. A vertex in no face is a warning; it stays in the mesh, so that indices remain
/// those of the file, and gets no mass from lumped_masses.
///
/// Why not Debian's tinyobjloader: it reads a malformed number such as `nan` or `abc` as 0
/// and skips unknown lines without a word, and it keeps no line per face, so a degenerate or
/// non-manifold face could not be named by its line.

#include <cstdint>
#include <string>
#include <vector>

#include "cloth/model/triangle_mesh.hpp"

namespace clothbench {

/// The largest mesh read_obj accepts; a bigger one is refused before it fills the memory.
struct ObjLimits {
  std::uint64_t max_bytes = 512ull << 20;  // bytes of the file (512 MiB)
  int max_vertices = 2000000;              // v lines
  int max_triangles = 4000000;             // triangles after polygons are split
};

/// An OBJ file read: its mesh and, to name a place in the file, the line of every vertex and
/// triangle.
struct ObjFile {
  cloth::TriangleMesh mesh;
  std::vector<int> vertex_line;       ///< #V 1-based line of each vertex's v
  std::vector<int> triangle_line;     ///< #T 1-based line of the f each triangle comes from
  std::vector<std::string> warnings;  ///< "PATH:LINE: ..." lines, for the user to read
};

/// Reads the OBJ file at path; throws UserError ("PATH:LINE: ..." or "PATH: cannot open ...")
/// for a file that cannot be a cloth, with the first five problems and how many more.
ObjFile read_obj_file(const std::string& path, ObjLimits limits = {});

/// The same for text held in memory, named name in messages (the byte limit applies to it).
ObjFile read_obj_text(const std::string& text, const std::string& name, ObjLimits limits = {});

/// Just the mesh of read_obj_file (its warnings dropped).
cloth::TriangleMesh read_obj(const std::string& path, ObjLimits limits = {});

}  // namespace clothbench
