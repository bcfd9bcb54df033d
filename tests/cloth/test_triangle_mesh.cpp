/// @file test_triangle_mesh.cpp
/// Triangle meshes: edges and bend pairs, lumped masses against hand-made meshes, check_mesh on
/// one hand-made mesh per problem, and the shape generator (determinism, validity, areas
/// against the inscribed polygons, boundaries, orientation, edge lengths).

#include <catch2/catch.hpp>
#include <cmath>
#include <map>

#include <Eigen/Geometry>

#include "cloth/model/mesh_check.hpp"
#include "cloth/model/mesh_generator.hpp"
#include "cloth/model/triangle_mesh.hpp"
#include "tolerances.hpp"

using namespace cloth;

namespace {

using Kind = MeshProblemKind;

TriangleMesh make_mesh(const std::vector<Vector3>& points, std::vector<std::array<int, 3>> tris) {
  TriangleMesh m;
  m.x.resize(3, static_cast<int>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) m.x.col(static_cast<int>(i)) = points[i];
  m.triangles = std::move(tris);
  return m;
}

/// Two triangles of areas 1 and 3 sharing the edge 1-2, both facing +z.
TriangleMesh two_triangles() {
  return make_mesh({{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {2, 3, 0}}, {{0, 1, 2}, {1, 3, 2}});
}

std::vector<Kind> kinds(const TriangleMesh& m) {
  std::vector<Kind> out;
  for (const MeshProblem& p : check_mesh(m)) out.push_back(p.kind);
  return out;
}

/// The boundary's closed loops, followed along the boundary edges (edges of one triangle),
/// each as its vertices; brute force over the triangles.
std::vector<std::vector<int>> boundary_loops(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> count;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  // the directed boundary edges: each boundary vertex has one way out on a manifold mesh
  std::map<int, int> next;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (count[{std::min(a, b), std::max(a, b)}] == 1) {
        REQUIRE(next.count(a) == 0);
        next[a] = b;
      }
    }
  std::vector<std::vector<int>> loops;
  while (!next.empty()) {
    std::vector<int> loop;
    for (int v = next.begin()->first; next.count(v);) {
      loop.push_back(v);
      const int w = next[v];
      next.erase(v);
      v = w;
    }
    loops.push_back(loop);
  }
  return loops;
}

Vector3 normal_of(const TriangleMesh& m, const std::array<int, 3>& t) {
  const Vector3 a = m.x.col(t[0]), b = m.x.col(t[1]), c = m.x.col(t[2]);
  return (b - a).cross(c - a);
}

double mean_edge_length(const TriangleMesh& m) {
  const MeshEdges e = mesh_edges(m);
  double sum = 0;
  for (const auto& ab : e.edges) sum += (m.x.col(ab[0]) - m.x.col(ab[1])).norm();
  return sum / static_cast<double>(e.edges.size());
}

/// Area of a regular n-gon inscribed in a circle of radius r.
double inscribed_polygon_area(int n, double r) {
  return 0.5 * n * r * r * std::sin(2 * M_PI / n);
}

ShapeSpec spec_of(MeshShape shape) {
  ShapeSpec s;
  s.shape = shape;
  s.radius = 0.15;
  s.inner_radius = 0.05;
  s.size_u = 0.3;
  s.size_v = 0.2;
  s.length = 0.2;
  s.edge_length = 0.02;
  s.center = {0.1, 1.0, -0.2};
  return s;
}

}  // namespace

TEST_CASE("mesh_edges lists each edge once and a bend pair per interior edge", "[mesh]") {
  const MeshEdges e = mesh_edges(two_triangles());
  const std::vector<std::array<int, 2>> edges = {{0, 1}, {0, 2}, {1, 2}, {1, 3}, {2, 3}};
  CHECK(e.edges == edges);
  // the one interior edge 1-2: opposite 0 in triangle 0 and 3 in triangle 1
  CHECK(e.bend_pairs == std::vector<std::array<int, 2>>{{0, 3}});
}

TEST_CASE("lumped masses give each vertex a third of its triangles' area", "[mesh]") {
  const TriangleMesh m = two_triangles();
  const double density = 0.5;  // kg/m^2
  const VectorX mass = lumped_masses(m, density);
  // areas 1 and 3 by hand: vertex 0 in the first, 3 in the second, 1 and 2 in both
  CHECK(mass[0] == Approx(density * 1.0 / 3));
  CHECK(mass[1] == Approx(density * 4.0 / 3));
  CHECK(mass[2] == Approx(density * 4.0 / 3));
  CHECK(mass[3] == Approx(density * 3.0 / 3));
  CHECK(mesh_area(m) == Approx(4.0));
  CHECK(mass.sum() == Approx(density * 4.0));
  // and on a generated disk: the masses add up to density times area
  const TriangleMesh disk = generate_mesh(spec_of(MeshShape::disk));
  CHECK(lumped_masses(disk, 0.2).sum() ==
        Approx(0.2 * mesh_area(disk)).epsilon(clothbench::tol::kMeshAreaRelative));
}

TEST_CASE("check_mesh finds each problem of hand-made meshes", "[mesh]") {
  const Vector3 o{0, 0, 0}, ex{1, 0, 0}, ey{0, 1, 0}, ez{0, 0, 1};
  CHECK(kinds(two_triangles()).empty());
  TriangleMesh nan = two_triangles();
  nan.x(1, 3) = std::nan("");
  CHECK(kinds(nan) == std::vector<Kind>{Kind::non_finite_vertex});
  CHECK(kinds(make_mesh({o, ex, ey}, {{0, 1, 5}})) ==
        std::vector<Kind>{Kind::index_out_of_range, Kind::unused_vertex});
  CHECK(kinds(make_mesh({o, ex, 2 * ex}, {{0, 1, 2}})) ==
        std::vector<Kind>{Kind::degenerate_triangle});
  CHECK(kinds(make_mesh({o, ex, ey}, {{0, 1, 1}})) ==
        std::vector<Kind>{Kind::degenerate_triangle, Kind::unused_vertex});
  // finite coordinates whose sides square to infinity: too large, not zero area
  CHECK(kinds(make_mesh({o, 1e200 * ex, 1e200 * ey}, {{0, 1, 2}})) ==
        std::vector<Kind>{Kind::oversized_triangle});
  // a fin: three triangles on the edge 0-1
  CHECK(kinds(make_mesh({o, ex, ey, ez, -ey}, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}})) ==
        std::vector<Kind>{Kind::non_manifold_edge});
  CHECK(kinds(make_mesh({o, ex, ey, ex + ey}, {{0, 1, 2}, {1, 2, 3}})) ==
        std::vector<Kind>{Kind::inconsistent_orientation});
  CHECK(kinds(make_mesh({o, ex, ey, -ex, -ey}, {{0, 1, 2}, {0, 3, 4}})) ==
        std::vector<Kind>{Kind::bowtie_vertex});
  const std::vector<MeshProblem> unused = check_mesh(make_mesh({o, ex, ey, ez}, {{0, 1, 2}}));
  REQUIRE(unused.size() == 1);
  CHECK(unused[0].kind == Kind::unused_vertex);
  CHECK(unused[0].vertex == 3);
  CHECK(!unused[0].is_error());
  CHECK(error_count(unused) == 0);
}

TEST_CASE("a closed fan around a vertex is no bowtie; two fans are", "[mesh]") {
  // a hexagon fan around vertex 0, then the same with one triangle taken out of each side
  std::vector<Vector3> p = {{0, 0, 0}};
  for (int k = 0; k < 6; ++k) p.emplace_back(std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0);
  std::vector<std::array<int, 3>> fan;
  for (int k = 0; k < 6; ++k) fan.push_back({0, 1 + k, 1 + (k + 1) % 6});
  CHECK(kinds(make_mesh(p, fan)).empty());
  CHECK(kinds(make_mesh(p, {fan[0], fan[1], fan[3], fan[4]})) ==
        std::vector<Kind>{Kind::bowtie_vertex});
}

TEST_CASE("the same seed gives the same mesh bit for bit, another seed another", "[mesh]") {
  const MeshShape shape =
      GENERATE(MeshShape::disk, MeshShape::annulus, MeshShape::rectangle, MeshShape::tube);
  ShapeSpec spec = spec_of(shape);
  const TriangleMesh a = generate_mesh(spec), b = generate_mesh(spec);
  CHECK((a.x.array() == b.x.array()).all());
  CHECK(a.triangles == b.triangles);
  spec.seed = 2;
  const TriangleMesh c = generate_mesh(spec);
  CHECK((a.x.cols() != c.x.cols() || !(a.x.array() == c.x.array()).all()));
}

TEST_CASE("every generated shape passes check_mesh and faces the way it should", "[mesh]") {
  const MeshShape shape =
      GENERATE(MeshShape::disk, MeshShape::annulus, MeshShape::rectangle, MeshShape::tube);
  const Plane plane = GENERATE(Plane::xz, Plane::xy);
  ShapeSpec spec = spec_of(shape);
  spec.plane = plane;
  spec.seed = 7;
  const TriangleMesh m = generate_mesh(spec);
  INFO("shape " << static_cast<int>(shape) << ", plane " << static_cast<int>(plane));
  CHECK(check_mesh(m).empty());
  // planar shapes face +y (xz) or +z (xy); a tube faces away from its axis
  const Vector3 up = plane == Plane::xz ? Vector3(0, 1, 0) : Vector3(0, 0, 1);
  int wrong = 0;
  for (const auto& t : m.triangles) {
    const Vector3 n = normal_of(m, t);
    Vector3 out = up;
    if (shape == MeshShape::tube) {
      out = (m.x.col(t[0]) + m.x.col(t[1]) + m.x.col(t[2])) / 3.0 - spec.center;
      out.y() = 0;
    }
    wrong += n.dot(out) <= 0;
  }
  CHECK(wrong == 0);
  // the mean edge within the 25% of the target
  CHECK(mean_edge_length(m) ==
        Approx(spec.edge_length).epsilon(clothbench::tol::kMeanEdgeLengthRelative));
}

TEST_CASE("a generated disk is its inscribed polygon, boundary exactly on the circle", "[mesh]") {
  ShapeSpec spec = spec_of(MeshShape::disk);
  const TriangleMesh m = generate_mesh(spec);
  const auto loops = boundary_loops(m);
  REQUIRE(loops.size() == 1);
  const int n = static_cast<int>(loops[0].size());
  for (int v : loops[0])
    CHECK(std::abs((m.x.col(v) - spec.center).norm() - spec.radius) <=
          clothbench::tol::kOnBoundaryRelative * spec.radius);
  CHECK(mesh_area(m) <= M_PI * spec.radius * spec.radius);
  CHECK(mesh_area(m) ==
        Approx(inscribed_polygon_area(n, spec.radius)).epsilon(clothbench::tol::kMeshAreaRelative));
}

TEST_CASE("a generated annulus has its hole empty and two boundaries", "[mesh]") {
  const ShapeSpec spec = spec_of(MeshShape::annulus);
  const TriangleMesh m = generate_mesh(spec);
  int inside = 0;
  for (const auto& t : m.triangles) {
    const Vector3 c = (m.x.col(t[0]) + m.x.col(t[1]) + m.x.col(t[2])) / 3.0;
    inside += (c - spec.center).norm() < spec.inner_radius;
  }
  CHECK(inside == 0);
  const auto loops = boundary_loops(m);
  REQUIRE(loops.size() == 2);
  // the outer polygon less the inner one
  std::vector<int> sizes;
  for (const auto& loop : loops) sizes.push_back(static_cast<int>(loop.size()));
  const double r0 = (m.x.col(loops[0][0]) - spec.center).norm();
  const bool first_outer = r0 > (spec.radius + spec.inner_radius) / 2;
  const int n_out = first_outer ? sizes[0] : sizes[1], n_in = first_outer ? sizes[1] : sizes[0];
  CHECK(mesh_area(m) == Approx(inscribed_polygon_area(n_out, spec.radius) -
                               inscribed_polygon_area(n_in, spec.inner_radius))
                            .epsilon(clothbench::tol::kMeshAreaRelative));
}

TEST_CASE("a generated rectangle covers its size exactly", "[mesh]") {
  const ShapeSpec spec = spec_of(MeshShape::rectangle);
  const TriangleMesh m = generate_mesh(spec);
  CHECK(mesh_area(m) ==
        Approx(spec.size_u * spec.size_v).epsilon(clothbench::tol::kMeshAreaRelative));
  const auto loops = boundary_loops(m);
  REQUIRE(loops.size() == 1);
  // every boundary vertex exactly on one of the four sides
  for (int v : loops[0]) {
    const double du = std::abs(m.x(0, v) - spec.center.x()),
                 dv = std::abs(m.x(2, v) - spec.center.z());
    CHECK((du == Approx(spec.size_u / 2).epsilon(1e-15) ||
           dv == Approx(spec.size_v / 2).epsilon(1e-15)));
    CHECK(m.x(1, v) == spec.center.y());
  }
}

TEST_CASE("a generated tube is closed around and open at two ends", "[mesh]") {
  const ShapeSpec spec = spec_of(MeshShape::tube);
  const TriangleMesh m = generate_mesh(spec);
  // every vertex on the cylinder, no two at the same place (the seam shares its points)
  for (int v = 0; v < m.vertex_count(); ++v) {
    const Vector3 d = m.x.col(v) - spec.center;
    CHECK(std::hypot(d.x(), d.z()) == Approx(spec.radius).epsilon(1e-14));
  }
  const auto loops = boundary_loops(m);
  REQUIRE(loops.size() == 2);
  for (const auto& loop : loops) {
    const double y = m.x(1, loop[0]);
    CHECK(std::abs(y - spec.center.y()) == Approx(spec.length / 2).epsilon(1e-14));
    for (int v : loop) CHECK(m.x(1, v) == y);
  }
  CHECK(mesh_area(m) < 2 * M_PI * spec.radius * spec.length);
  CHECK(mesh_area(m) > 0.95 * 2 * M_PI * spec.radius * spec.length);
}

TEST_CASE("shapes that cannot be generated are named, not made", "[mesh]") {
  ShapeSpec narrow = spec_of(MeshShape::annulus);
  narrow.inner_radius = narrow.radius - 0.5 * narrow.edge_length;
  CHECK(shape_spec_problem(narrow).rfind("edge_length:", 0) == 0);
  CHECK_THROWS_AS(generate_mesh(narrow), std::invalid_argument);
  ShapeSpec thin = spec_of(MeshShape::tube);
  thin.radius = 5 * thin.edge_length / (2 * M_PI);  // five edges around
  CHECK(shape_spec_problem(thin).rfind("edge_length:", 0) == 0);
  // a disk as coarse (a polygon of five sides is not the shape; an annulus is held to one
  // edge across its ring, which is stricter), and a rectangle narrower than one edge
  ShapeSpec coarse = spec_of(MeshShape::disk);
  coarse.edge_length = 2 * M_PI * coarse.radius / 5;
  CHECK(shape_spec_problem(coarse).rfind("edge_length: a disk needs at least six edges around",
                                         0) == 0);
  coarse.edge_length = 2 * M_PI * coarse.radius / 6.5;
  CHECK(shape_spec_problem(coarse).empty());
  ShapeSpec strip = spec_of(MeshShape::rectangle);
  strip.edge_length = 1.01 * std::min(strip.size_u, strip.size_v);
  CHECK(shape_spec_problem(strip).rfind("edge_length: at most the rectangle's shorter side", 0) ==
        0);
  strip.edge_length = std::min(strip.size_u, strip.size_v);
  CHECK(shape_spec_problem(strip).empty());
  ShapeSpec huge = spec_of(MeshShape::rectangle);
  huge.edge_length = 1e-4;  // 0.06 m^2 / (8.7e-9 m^2 per vertex): 6.9 million vertices
  CHECK(shape_spec_problem(huge).find("more than 2000000 vertices") != std::string::npos);
  ShapeSpec no_radius = spec_of(MeshShape::disk);
  no_radius.radius = std::nan("");
  CHECK(shape_spec_problem(no_radius) == "radius: expected a number > 0");
  CHECK(shape_spec_problem(spec_of(MeshShape::disk)).empty());
}
