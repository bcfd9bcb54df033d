/// @file test_obj_reader.cpp
/// The OBJ reader on good files (polygons split, every face form, negative indices, groups)
/// and on one bad file per problem, each refused with the line that holds it.

#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "cloth/model/triangle_mesh.hpp"
#include "harness/io/obj_reader.hpp"
#include "harness/io/user_error.hpp"

using namespace clothbench;
namespace fs = std::filesystem;

namespace {

const fs::path kSource = CLOTHBENCH_SOURCE_DIR;

std::string good(const char* name) {
  return (kSource / "tests/data/good/meshes" / name).string();
}
std::string bad(const char* name) {
  return (kSource / "tests/data/bad/meshes" / name).string();
}

/// The message of the UserError reading path throws; fails the test when it throws none.
std::string error_of(const std::string& path, ObjLimits limits = {}) {
  try {
    read_obj_file(path, limits);
  } catch (const UserError& e) {
    return e.what();
  }
  FAIL("no UserError was thrown for " << path);
  return "";
}

using Tri = std::array<int, 3>;

}  // namespace

TEST_CASE("quads and polygons are split as fans, in file order", "[mesh]") {
  const ObjFile f = read_obj_file(good("quads.obj"));
  CHECK(f.mesh.vertex_count() == 11);
  // two quads (two triangles each) and a pentagon (three), fans around each face's first vertex
  const std::vector<Tri> expected = {{0, 3, 4},  {0, 4, 1}, {1, 4, 5}, {1, 5, 2},
                                     {6, 10, 9}, {6, 9, 8}, {6, 8, 7}};
  CHECK(f.mesh.triangles == expected);
  CHECK(f.triangle_line == std::vector<int>{8, 8, 9, 9, 15, 15, 15});
  CHECK(f.vertex_line[0] == 2);
  CHECK(f.vertex_line[6] == 10);
  CHECK(f.warnings.empty());
  // two unit squares and a pentagon of area 2.5 (shoelace by hand)
  CHECK(cloth::mesh_area(f.mesh) == Approx(4.5).epsilon(1e-14));
  CHECK(f.mesh.x(0, 8) == 6.5);
}

TEST_CASE("every form of a face's vertex reads the vertex alone", "[mesh]") {
  const ObjFile f = read_obj_file(good("slash_forms.obj"));
  CHECK(f.mesh.vertex_count() == 5);
  CHECK(f.mesh.triangles == std::vector<Tri>{{0, 2, 1}, {0, 3, 2}, {1, 2, 4}});
  CHECK(f.warnings.empty());
}

TEST_CASE("negative indices count back from the last vertex so far", "[mesh]") {
  const ObjFile f = read_obj_file(good("negative_indices.obj"));
  CHECK(f.mesh.triangles == std::vector<Tri>{{0, 2, 1}, {1, 2, 3}});
}

TEST_CASE("g and o names become vertex groups of their faces' vertices", "[mesh]") {
  const ObjFile f = read_obj_file(good("groups.obj"));
  using Group = std::pair<std::string, std::vector<int>>;
  // o starts an object and clears the g names; g with two names puts a face in both
  const std::vector<Group> expected = {{"lower", {0, 1, 2, 3}},
                                       {"hem", {0, 1, 2, 3, 4, 5, 6}},
                                       {"corner", {0, 2, 3}},
                                       {"upper", {4, 5, 6, 7}}};
  CHECK(f.mesh.groups == expected);
  CHECK(f.mesh.triangle_count() == 4);
}

TEST_CASE("a missing file is refused by name", "[mesh]") {
  const std::string path = bad("no_such_mesh.obj");
  CHECK(error_of(path).rfind(path + ": cannot open", 0) == 0);
}

TEST_CASE("each bad mesh is refused with the line that holds the problem", "[mesh]") {
  struct Case {
    const char* file;
    int line;
    const char* words;
  };
  const Case cases[] = {
      {"index_out_of_range.obj", 7, "refers to vertex 7, but the file has 4 vertices"},
      {"zero_index.obj", 5, "vertex reference 0"},
      {"degenerate_triangle.obj", 7, "degenerate triangle (vertices 1, 2, 4)"},
      {"nan_coordinate.obj", 3, "not a finite number"},
      {"inf_coordinate.obj", 4, "not a finite number"},
      {"huge_coordinate.obj", 4, "out of the range of a double"},
      {"oversized_triangle.obj", 5, "triangle (vertices 1, 3, 2) too large to measure"},
      {"bad_number.obj", 3, "expected a number as vertex coordinate, got \"0,5\""},
      {"edge_three_triangles.obj", 9, "edge between vertices 1 and 2 is shared by more than two"},
      {"bowtie.obj", 2, "vertex 1 is where separate fans of faces meet"},
      {"inconsistent_orientation.obj", 7, "the same way as the face on line 6"},
      {"face_two_vertices.obj", 5, "at least 3 vertices, got 2"},
      {"unknown_statement.obj", 6, "unknown statement \"solid\""},
  };
  for (const Case& c : cases) {
    const std::string path = bad(c.file);
    const std::string message = error_of(path);
    INFO(message);
    CHECK(message.rfind(path + ":" + std::to_string(c.line) + ": ", 0) == 0);
    CHECK(message.find(c.words) != std::string::npos);
  }
}

TEST_CASE("a mesh without faces is refused", "[mesh]") {
  const std::string path = bad("no_faces.obj");
  CHECK(error_of(path) == path + ": no faces (f lines): not a triangle mesh");
}

TEST_CASE("an unused vertex is a warning with its line, and the mesh loads", "[mesh]") {
  const std::string path = bad("unused_vertex.obj");
  const ObjFile f = read_obj_file(path);
  REQUIRE(f.warnings.size() == 1);
  CHECK(f.warnings[0] == path + ":5: vertex 4 is in no face (kept, with no mass)");
  CHECK(f.mesh.vertex_count() == 4);
  CHECK(cloth::lumped_masses(f.mesh, 1.0)[3] == 0.0);
}

TEST_CASE("meshes over the size limits are refused with the limit named", "[mesh]") {
  const std::string path = good("quads.obj");
  ObjLimits few_vertices;
  few_vertices.max_vertices = 10;
  CHECK(error_of(path, few_vertices) ==
        path + ":14: more than 10 vertices, the most a mesh may have");
  ObjLimits few_triangles;
  few_triangles.max_triangles = 6;
  CHECK(error_of(path, few_triangles) ==
        path + ":15: more than 6 triangles, the most a mesh may have");
  ObjLimits few_bytes;
  few_bytes.max_bytes = 100;
  const std::string message = error_of(path, few_bytes);
  CHECK(message.rfind(
            path + ": " + std::to_string(fs::file_size(path)) + " bytes, more than the 100", 0) ==
        0);
}

TEST_CASE("many problems are told five at a time, then how many more", "[mesh]") {
  // seven separate degenerate triangles
  std::string text;
  for (int k = 0; k < 7; ++k) text += "v 0 0 0\nv 1 0 0\nv 2 0 0\nf -3 -2 -1\n";
  try {
    read_obj_text(text, "many.obj");
    FAIL("no UserError");
  } catch (const UserError& e) {
    const std::string m = e.what();
    CHECK(m.rfind("many.obj:4: degenerate triangle", 0) == 0);
    CHECK(m.find("many.obj:20: degenerate triangle") != std::string::npos);
    CHECK(m.find("many.obj:24:") == std::string::npos);
    CHECK(m.substr(m.size() - 12) == "; and 2 more");
  }
}

TEST_CASE("read_obj_text reads what read_obj_file reads", "[mesh]") {
  const ObjFile a = read_obj_file(good("groups.obj"));
  const ObjFile b = read_obj_text(
      "o lower\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\ng hem corner\nf 1 4 3\ng hem\nf 1 3 2\n"
      "o upper\nv 0 0.1 0\nv 1 0.1 0\nv 1 0.1 1\nv 0 0.1 1\nf 5 8 7\ng hem\nf 5 7 6\n",
      "text.obj");
  CHECK(a.mesh.x == b.mesh.x);
  CHECK(a.mesh.triangles == b.mesh.triangles);
  CHECK(a.mesh.groups == b.mesh.groups);
}
