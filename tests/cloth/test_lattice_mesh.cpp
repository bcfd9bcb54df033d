/// @file test_lattice_mesh.cpp
/// The generator's grid lattice (lattice = "grid"): vertex counts from the index grid, the
/// rectangle covered exactly, check_mesh clean, the yarns (structural links) at the lattice
/// angle and the shear links along the squares' diagonals, and the refused angles.

#include <catch2/catch.hpp>
#include <cmath>

#include "cloth/model/mesh_check.hpp"
#include "cloth/model/mesh_generator.hpp"
#include "cloth/model/triangle_mesh.hpp"
#include "tolerances.hpp"

using namespace cloth;

namespace {

/// A 150 mm x 50 mm strip in the xz plane: at 45 degrees with h = 5 sqrt(2) mm, 30 by 10
/// half-diagonal steps of 5 mm; at 0 degrees with h = 5 mm, 30 by 10 squares.
ShapeSpec strip(double angle, Plane plane) {
  ShapeSpec s;
  s.shape = MeshShape::rectangle;
  s.lattice = MeshLattice::grid;
  s.lattice_angle = angle;
  s.size_u = 0.15;
  s.size_v = 0.05;
  s.edge_length = std::lround(angle / 45.0) % 2 ? 0.005 * std::sqrt(2.0) : 0.005;
  s.center = {0.1, 0.5, -0.2};
  s.plane = plane;
  return s;
}

/// The in-plane (u, v) components of a link's direction, unit.
Eigen::Vector2d direction(const TriangleMesh& m, const std::array<int, 2>& l, Plane plane) {
  const Vector3 d = m.x.col(l[1]) - m.x.col(l[0]);
  const Eigen::Vector2d uv(d.x(), plane == Plane::xz ? d.z() : d.y());
  return uv.normalized();
}

}  // namespace

TEST_CASE("a 45-degree grid lattice: its nodes, its rectangle, yarns at 45 degrees", "[mesh]") {
  const Plane plane = GENERATE(Plane::xz, Plane::xy);
  const double angle = GENERATE(45.0, -45.0, 135.0);
  const ShapeSpec spec = strip(angle, plane);
  const TriangleMesh m = generate_mesh(spec);
  CHECK(check_mesh(m).empty());
  // the nodes (i, j) of a 31 by 11 index grid with i + j even: (31 * 11 + 1) / 2
  CHECK(m.vertex_count() == 171);
  // the rectangle covered exactly: whole diamonds inside, half diamonds along the edges
  CHECK(mesh_area(m) == Approx(0.15 * 0.05).epsilon(clothbench::tol::kMeshAreaRelative));
  const LatticeLinks l = lattice_links(m);
  // every yarn side at +-45 degrees to u, of length h; every diagonal along u or along v
  const double c45 = std::sqrt(0.5);
  int plus = 0, minus = 0;
  for (const auto& s : l.structural) {
    const Eigen::Vector2d d = direction(m, s, plane);
    CHECK(std::abs(d.x()) == Approx(c45).epsilon(1e-12));
    CHECK(std::abs(d.y()) == Approx(c45).epsilon(1e-12));
    (d.x() * d.y() > 0 ? plus : minus) += 1;
    CHECK((m.x.col(s[1]) - m.x.col(s[0])).norm() == Approx(spec.edge_length).epsilon(1e-12));
  }
  // the two yarn families alike (the strip is symmetric across its axis)
  CHECK(plus == minus);
  for (const auto& s : l.shear) {
    const Eigen::Vector2d d = direction(m, s, plane);
    CHECK(std::min(std::abs(d.x()), std::abs(d.y())) <= 1e-12);
  }
  // bend pairs two yarn sides apart: along +-45 degrees again, length 2 h
  REQUIRE_FALSE(l.bend.empty());
  for (const auto& b : l.bend) {
    CHECK(std::abs(direction(m, b, plane).x()) == Approx(c45).epsilon(1e-12));
    CHECK((m.x.col(b[1]) - m.x.col(b[0])).norm() == Approx(2 * spec.edge_length).epsilon(1e-12));
  }
  // every pair of vertices h apart is a yarn side, each once (brute force over the pairs)
  int at_h = 0;
  for (int a = 0; a < m.vertex_count(); ++a)
    for (int b = a + 1; b < m.vertex_count(); ++b)
      at_h += std::abs((m.x.col(a) - m.x.col(b)).norm() - spec.edge_length) < 1e-9;
  CHECK(int(l.structural.size()) == at_h);
}

TEST_CASE("a 0-degree grid lattice is the grid: squares along u and v", "[mesh]") {
  const Plane plane = GENERATE(Plane::xz, Plane::xy);
  const ShapeSpec spec = strip(GENERATE(0.0, 90.0), plane);
  const TriangleMesh m = generate_mesh(spec);
  CHECK(check_mesh(m).empty());
  CHECK(m.vertex_count() == 31 * 11);
  CHECK(mesh_area(m) == Approx(0.15 * 0.05).epsilon(clothbench::tol::kMeshAreaRelative));
  const LatticeLinks l = lattice_links(m);
  // the grid's counts: 30 * 11 + 31 * 10 sides, two diagonals per square, bends two apart
  CHECK(l.structural.size() == 30 * 11 + 31 * 10);
  CHECK(l.shear.size() == 2 * 30 * 10);
  CHECK(l.bend.size() == 29 * 11 + 31 * 9);
  for (const auto& s : l.structural) {
    const Eigen::Vector2d d = direction(m, s, plane);
    CHECK(std::min(std::abs(d.x()), std::abs(d.y())) <= 1e-12);
  }
}

TEST_CASE("a grid lattice at another angle or on another shape is refused", "[mesh]") {
  ShapeSpec s = strip(30.0, Plane::xz);
  CHECK(shape_spec_problem(s).rfind("lattice_angle: expected a multiple of 45", 0) == 0);
  CHECK_THROWS_AS(generate_mesh(s), std::invalid_argument);
  s.lattice_angle = std::nan("");
  CHECK(shape_spec_problem(s).rfind("lattice_angle:", 0) == 0);
  s = strip(45.0, Plane::xz);
  s.shape = MeshShape::disk;
  CHECK(shape_spec_problem(s).rfind("lattice:", 0) == 0);
  s = strip(45.0, Plane::xz);
  s.lattice = MeshLattice::triangular;
  CHECK(shape_spec_problem(s).rfind("lattice_angle: applies", 0) == 0);
  // a triangular rectangle has no cells: its springs follow its edges
  s.lattice_angle = 0.0;
  CHECK(generate_mesh(s).cells.empty());
}
