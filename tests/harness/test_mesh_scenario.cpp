// A cloth of any outline through the scenario file: meshes read and generated, their masses and
// springs, their selections, the errors a user can make, and physical facts of a mesh run in
// every engine (free fall, self-intersection measured the same way).

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "cloth/analysis/self_intersection.hpp"
#include "cloth/forces/spring_forces.hpp"
#include "cloth/model/mesh_generator.hpp"
#include "cloth/model/model.hpp"
#include "cloth/model/triangle_mesh.hpp"
#include "harness/io/obj_reader.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "temp_dir.hpp"
#include "tolerances.hpp"

using namespace clothbench;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const fs::path kSource = CLOTHBENCH_SOURCE_DIR;

/// A generated disk of radius 0.1 m, 2.5 cm edges, 0.2 kg/m^2, and the engines given.
std::string disk_scenario(const std::string& engines, const std::string& extra = "") {
  return R"(
name = "disk"
duration = 0.2
frame_interval = 0.01
gravity = [0.0, -9.8, 0.0]
[cloth]
areal_density = 0.2
stiffness = { structural = 50.0, bend = 5.0 }
damping = 0.01
[cloth.generate]
shape = "disk"
radius = 0.1
edge_length = 0.025
center = [0.0, 1.0, 0.0]
)" + extra +
         engines;
}

const char* const kCustomRk4 = R"(
[[engine]]
name = "custom-rk4"
kind = "custom"
integrator = "rk4"
dt = 5e-4
)";

const char* const kEveryKind = R"(
[[engine]]
name = "custom-rk4"
kind = "custom"
integrator = "rk4"
dt = 5e-4
[[engine]]
name = "bullet-deformable"
kind = "bullet-deformable"
implicit = false
dt = 5e-4
[[engine]]
name = "bullet-softbody"
kind = "bullet-softbody"
dt = 5e-4
)";

/// The message parse_scenario throws for text, or "" when it loads.
std::string refusal(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    parse_scenario(text, "mesh.toml", sets);
  } catch (const UserError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a generated mesh: masses from its area, one spring per edge and interior edge",
          "[mesh][scenario]") {
  const Scenario sc = parse_scenario(disk_scenario(kCustomRk4), "disk.toml");
  REQUIRE(sc.scene.mesh);
  const cloth::TriangleMesh& mesh = *sc.scene.mesh;
  const cloth::Model m = cloth::build_model(sc.scene);
  CHECK(m.is_mesh);
  CHECK(m.particle_count() == mesh.vertex_count());
  CHECK(m.triangles == mesh.triangles);
  // lumped masses: density times area, shared a third per corner
  CHECK(m.mass.sum() == Approx(0.2 * cloth::mesh_area(mesh)).epsilon(tol::kMeshAreaRelative));
  const cloth::MeshEdges e = cloth::mesh_edges(mesh);
  CHECK(m.springs.count() == static_cast<int>(e.edges.size() + e.bend_pairs.size()));
  CHECK(m.springs.families.empty());
  // at rest: no spring stretched, nothing crossing
  const cloth::StrainStats st = cloth::strain_stats(m.springs, m.x0);
  CHECK(st.max_abs == 0.0);
  const cloth::SelfIntersection si =
      cloth::SelfIntersectionMeter(m.particle_count(), m.triangles, 0.01).measure(m.x0);
  CHECK(si.crossings == 0);
}

TEST_CASE("total_mass spreads by area on a mesh, areal_density by size on a grid",
          "[mesh][scenario]") {
  const Scenario sc =
      parse_scenario(disk_scenario(kCustomRk4), "disk.toml", {"cloth.total_mass=0.5"});
  CHECK(cloth::build_model(sc.scene).mass.sum() == Approx(0.5).epsilon(tol::kMeshAreaRelative));
  const Scenario grid = parse_scenario(R"(
[cloth]
particles = [4, 5]
size = [2.0, 0.5]
areal_density = 0.3
)" + std::string(kCustomRk4),
                                       "grid.toml");
  const cloth::Model g = cloth::build_model(grid.scene);
  CHECK(g.mass.sum() == Approx(0.3 * 2.0 * 0.5));
  CHECK(g.mass.minCoeff() == g.mass.maxCoeff());
}

TEST_CASE("a mesh falls exactly: no spring works on a rigid translation", "[mesh][integrator]") {
  // rk4 integrates constant acceleration exactly; nothing is held, nothing collides
  const Scenario sc = parse_scenario(disk_scenario(kCustomRk4), "disk.toml");
  RunOptions o;
  o.progress = false;
  const RunResult r = run_scenario(sc, o);
  const EngineRun& run = r.runs.front();
  REQUIRE(run.stable);
  const double t = sc.duration;
  const double y0 = r.model.x0.row(1).mean();
  CHECK(run.frames.back().com.y() == Approx(y0 - 0.5 * 9.8 * t * t).margin(tol::kFreeFallExact));
  // every vertex, not just the centre of mass
  const cloth::Matrix3X& x = run.positions.back();
  CHECK((x.row(1).array() - (r.model.x0.row(1).array() - 0.5 * 9.8 * t * t)).abs().maxCoeff() <
        tol::kFreeFallExact);
  CHECK(run.frames.back().max_stretch < 1e-9);
}

TEST_CASE("every engine builds the mesh and is measured the same way", "[mesh][bullet]") {
  const Scenario sc = parse_scenario(disk_scenario(kEveryKind), "disk.toml");
  RunOptions o;
  o.progress = false;
  const RunResult r = run_scenario(sc, o);
  REQUIRE(r.runs.size() == 3);
  for (const EngineRun& run : r.runs) {
    INFO(run.spec.name);
    CHECK(run.stable);
    CHECK(run.positions.back().cols() == r.model.particle_count());
    // a disk falling flat does not meet itself
    CHECK(run.frames.back().self_intersections == 0);
    CHECK(run.frames.back().min_self_distance > 0);
    // the same fall: every engine's centre within a millimetre of the exact one after 0.2 s
    CHECK(run.frames.back().com.y() == Approx(1.0 - 0.5 * 9.8 * 0.04).margin(1e-3));
  }
}

TEST_CASE("mesh selections: groups, vertex indices, balls and boxes", "[mesh][scenario]") {
  const fs::path skirt = kSource / "scenarios" / "meshes" / "skirt.obj";
  const std::string base = R"(
[cloth]
mesh = ")" + skirt.string() +
                           R"("
areal_density = 0.2
stiffness = { structural = 50.0, bend = 5.0 }
)" + std::string(kCustomRk4);
  SECTION("a group holds the vertices of its faces: the waistband's two rings") {
    const Scenario sc = parse_scenario(
        base + "[[constraint]]\nselect = \"group\"\nname = \"waistband\"\n", "skirt.toml");
    int held = 0;
    for (std::uint8_t h : sc.scene.held) held += h != 0;
    CHECK(held == 72);  // 36 vertices a ring
  }
  SECTION("indices are 0-based vertex indices") {
    const Scenario sc = parse_scenario(
        base + "[[constraint]]\nselect = \"indices\"\nlist = [0, 575]\nhold = \"y\"\n",
        "skirt.toml");
    CHECK(sc.scene.held[0] == cloth::kHoldY);
    CHECK(sc.scene.held[575] == cloth::kHoldY);
    CHECK(sc.scene.held[1] == 0);
  }
  SECTION("a box of rest positions: the top ring") {
    const Scenario sc = parse_scenario(
        base +
            "[[constraint]]\nselect = \"box\"\nmin = [-1.0, 0.999, -1.0]\nmax = [1.0, 1.1, 1.0]\n",
        "skirt.toml");
    int held = 0;
    for (std::uint8_t h : sc.scene.held) held += h != 0;
    CHECK(held == 36);
  }
  SECTION("a ball on a grid too") {
    const Scenario sc = parse_scenario(R"(
[cloth]
particles = [5, 5]
size = [4.0, 4.0]
center = [0.0, 0.0, 0.0]
[[constraint]]
select = "within"
center = [2.0, 0.0, 2.0]
radius = 1.0
)" + std::string(kCustomRk4),
                                       "grid.toml");
    // the corner (4, 4) and its two neighbours at exactly 1 m
    int held = 0;
    for (std::uint8_t h : sc.scene.held) held += h != 0;
    CHECK(held == 3);
    CHECK(sc.scene.held[24] == cloth::kHoldAll);
  }
}

TEST_CASE("mesh scenarios refuse what a mesh cannot have, naming the key", "[mesh][scenario]") {
  const std::string d = disk_scenario(kCustomRk4);
  CHECK_THAT(refusal(d, {"cloth.stiffness.shear=10"}),
             Contains("cloth.stiffness.shear: a mesh has no shear springs"));
  CHECK_THAT(refusal(d, {"cloth.particles=[3,3]"}),
             Contains("cloth.particles: applies to a grid, not to a mesh cloth"));
  CHECK_THAT(refusal(d, {"cloth.mesh=\"x.obj\""}),
             Contains("expected mesh = \"file.obj\" or a [cloth.generate] table, got both"));
  CHECK_THAT(
      refusal(d, {"cloth.generate.edge_length=1e-5"}),
      Contains("--set cloth.generate.edge_length: too small, the mesh would have more than"));
  CHECK_THAT(refusal(d, {"cloth.generate.shape=\"cone\""}), Contains("cloth.generate.shape"));
  CHECK_THAT(refusal(d, {"cloth.generate.length=0.3"}),
             Contains("cloth.generate.length: applies to other shapes"));
  CHECK_THAT(refusal(disk_scenario(kCustomRk4, "[[constraint]]\nselect = \"corners\"\n")),
             Contains("constraint.0.select: selects on a grid"));
  CHECK_THAT(
      refusal(disk_scenario(kCustomRk4, "[[constraint]]\nselect = \"group\"\nname = \"rim\"\n")),
      Contains("constraint.0.name: expected a group of the mesh (it has none)"));
  CHECK_THAT(
      refusal(disk_scenario(kCustomRk4, "[[constraint]]\nselect = \"indices\"\nlist = [100000]\n")),
      Contains("constraint.0.list.0: expected a vertex index from 0 to"));
  CHECK_THAT(refusal(disk_scenario(
                 kCustomRk4,
                 "[[constraint]]\nselect = \"within\"\ncenter = [5.0, 5.0, 5.0]\nradius = 0.1\n")),
             Contains("expected a ball that holds at least one particle's rest position"));
  // the mass: one way, and a mesh needs one
  CHECK_THAT(refusal(d, {"cloth.particle_mass=0.1"}),
             Contains("cloth.particle_mass: a mesh's vertices weigh what their share of its area"));
}

TEST_CASE("a mesh file is read relative to the scenario file; a bad one names its line",
          "[mesh][scenario]") {
  clothbench::test::TempDir dir("mesh-scenario");
  fs::create_directories(dir.path / "meshes");
  {
    std::ofstream obj(dir.path / "meshes" / "tri.obj");
    obj << "v 0 1 0\nv 1 1 0\nv 0 1 1\nv 1 1 1\nf 1 3 2\nf 2 3 4\n";
    std::ofstream bad(dir.path / "meshes" / "bad.obj");
    bad << "v 0 1 0\nv 1 1 0\nv 0 1 1\nf 1 2 3\nf 1 2 9\n";
  }
  const std::string scenario =
      std::string("[cloth]\nmesh = \"meshes/tri.obj\"\ntotal_mass = 0.1\n") + kCustomRk4;
  {
    std::ofstream f(dir.path / "s.toml");
    f << scenario;
  }
  const Scenario sc = load_scenario((dir.path / "s.toml").string());
  REQUIRE(sc.scene.mesh);
  CHECK(sc.scene.particle_count() == 4);
  CHECK(sc.mesh.file == "meshes/tri.obj");
  {
    std::ofstream f(dir.path / "s.toml");
    f << "[cloth]\nmesh = \"meshes/bad.obj\"\ntotal_mass = 0.1\n" << kCustomRk4;
  }
  try {
    load_scenario((dir.path / "s.toml").string());
    FAIL("a face index out of range loaded");
  } catch (const UserError& e) {
    CHECK_THAT(std::string(e.what()), Contains("bad.obj:5:"));
  }
}

TEST_CASE("a mesh whose rest shape crosses itself loads with a warning, counted from frame 0",
          "[mesh][selfintersection]") {
  // two napkins (two pieces of one file): the second stands upright through the first
  clothbench::test::TempDir dir("mesh-crossing");
  fs::create_directories(dir.path);
  {
    std::ofstream obj(dir.path / "two.obj");
    obj << "o flat\nv -1 1 -1\nv 1 1 -1\nv -1 1 1\nv 1 1 1\nf 1 3 2\nf 2 3 4\n"
        << "o upright\nv -0.5 0.5 0.1\nv 0.5 0.5 0.1\nv -0.5 1.5 0.1\nv 0.5 1.5 0.1\n"
        << "f 5 6 7\nf 6 8 7\n";
    std::ofstream f(dir.path / "s.toml");
    f << "duration = 0.01\nframe_interval = 0.01\n[cloth]\nmesh = \"two.obj\"\n"
      << "total_mass = 0.1\n"
      << kCustomRk4;
  }
  const Scenario sc = load_scenario((dir.path / "s.toml").string());
  REQUIRE(sc.warnings.size() == 1);
  CHECK_THAT(sc.warnings[0], Contains("the rest shape crosses itself"));
  RunOptions o;
  o.progress = false;
  const RunResult r = run_scenario(sc, o);
  // the planes meet along y = 1, z = 0.1, x in [-0.5, 0.5]. Upright edges through y = 1: 5-7
  // at x = -0.5 (in the flat triangle x + z < 0), 6-8 at x = 0.5 and the diagonal 6-7 at x = 0
  // (both in the flat triangle x + z > 0); the flat diagonal 2-3 (x = -z) meets z = 0.1 at
  // x = -0.1, inside the upright triangle x + y < 1: four crossings
  CHECK(r.runs.front().frames.front().self_intersections == 4);
  // the distance is between elements, not edge to triangle: the two diagonals, the lines
  // (t, 1, -t) and (s, 1 - s, 0.1), pass 0.1 / sqrt(3) m apart
  CHECK(r.runs.front().frames.front().min_self_distance == Approx(0.1 / std::sqrt(3.0)));
}

TEST_CASE("a mesh file without a size (a device) is read no further than the limit",
          "[mesh][scenario]") {
  ObjLimits small;
  small.max_bytes = 4096;
  // /dev/zero never ends and has no size to check first: one endless line of NULs
  CHECK_THROWS_WITH(read_obj_file("/dev/zero", small),
                    Contains("/dev/zero: more than the 4096 bytes a mesh file may have"));
}
