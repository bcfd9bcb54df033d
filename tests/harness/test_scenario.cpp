// Scenario files: strict validation with located messages, --set overrides, the resolved
// TOML round trip, the embedded default and the selections of held particles.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>

#include "cloth/model/model.hpp"
#include "harness/io/toml_text.hpp"
#include "harness/scenario/scenario.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_writer.hpp"

namespace fs = std::filesystem;
using namespace clothbench;
using Catch::Matchers::Contains;

namespace {

const fs::path kSource = CLOTHBENCH_SOURCE_DIR;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Every *.toml file in dir, sorted.
std::vector<fs::path> toml_files(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// The message of the ScenarioError f throws; fails the test when it throws none.
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ScenarioError& e) {
    return e.what();
  }
  FAIL("no ScenarioError was thrown");
  return "";
}

std::string seed_path() {
  return (kSource / "scenarios" / "seed_sphere_drape.toml").string();
}

std::string set_error(const std::vector<std::string>& overrides) {
  return error_of([&] { load_scenario(seed_path(), overrides); });
}

void check_same_scene(const cloth::Scene& a, const cloth::Scene& b) {
  const cloth::ClothParams &x = a.cloth, &y = b.cloth;
  CHECK(x.nu == y.nu);
  CHECK(x.nv == y.nv);
  CHECK(x.size_u == y.size_u);
  CHECK(x.size_v == y.size_v);
  CHECK(x.center == y.center);
  CHECK(x.plane == y.plane);
  CHECK(x.particle_mass == y.particle_mass);
  CHECK(x.total_mass == y.total_mass);
  CHECK(x.k_structural == y.k_structural);
  CHECK(x.k_shear == y.k_shear);
  CHECK(x.k_bend == y.k_bend);
  CHECK(x.self_collision == y.self_collision);
  CHECK(x.thickness == y.thickness);
  CHECK(x.self_friction == y.self_friction);
  CHECK(x.damping == y.damping);
  CHECK(x.air_drag == y.air_drag);
  CHECK(a.gravity == b.gravity);
  REQUIRE(a.spheres.size() == b.spheres.size());
  for (size_t k = 0; k < a.spheres.size(); ++k) {
    const cloth::Sphere &s = a.spheres[k], &t = b.spheres[k];
    CHECK(s.center == t.center);
    CHECK(s.radius == t.radius);
    CHECK(s.restitution == t.restitution);
    CHECK(s.friction == t.friction);
    CHECK(s.velocity == t.velocity);
    CHECK(s.margin == t.margin);
  }
  CHECK(a.held == b.held);
}

/// Every field of two scenarios but source.
void check_same_scenario(const Scenario& a, const Scenario& b) {
  CHECK(a.name == b.name);
  CHECK(a.description == b.description);
  CHECK(a.duration == b.duration);
  CHECK(a.frame_interval == b.frame_interval);
  CHECK(a.snapshot_interval == b.snapshot_interval);
  CHECK(a.animation_interval == b.animation_interval);
  CHECK(a.blowup_strain == b.blowup_strain);
  CHECK(a.blowup_energy == b.blowup_energy);
  CHECK(a.reference == b.reference);
  check_same_scene(a.scene, b.scene);
  REQUIRE(a.constraints.size() == b.constraints.size());
  for (size_t k = 0; k < a.constraints.size(); ++k) {
    const ConstraintSpec &c = a.constraints[k], &d = b.constraints[k];
    CHECK(c.select == d.select);
    CHECK(c.hold == d.hold);
    CHECK(c.disk_center_x == d.disk_center_x);
    CHECK(c.disk_center_z == d.disk_center_z);
    CHECK(c.disk_radius == d.disk_radius);
    CHECK(c.indices == d.indices);
  }
  REQUIRE(a.engines.size() == b.engines.size());
  for (size_t k = 0; k < a.engines.size(); ++k) {
    const EngineSpec &e = a.engines[k], &f = b.engines[k];
    CHECK(e.name == f.name);
    CHECK(e.kind == f.kind);
    CHECK(e.dt == f.dt);
    CHECK(e.solver.integrator == f.solver.integrator);
    CHECK(e.solver.newton_iterations == f.solver.newton_iterations);
    CHECK(e.solver.cg_tolerance == f.solver.cg_tolerance);
    CHECK(e.solver.cg_max_iterations == f.solver.cg_max_iterations);
    CHECK(e.solver.cg_forcing == f.solver.cg_forcing);
    CHECK(e.solver.contacts == f.solver.contacts);
    CHECK(e.solver.clamp_compressed == f.solver.clamp_compressed);
    CHECK(e.solver.clamped_iterations == f.solver.clamped_iterations);
    CHECK(e.solver.linear_solver == f.solver.linear_solver);
    CHECK(e.bullet.implicit == f.bullet.implicit);
    CHECK(e.bullet.line_search == f.bullet.line_search);
    CHECK(e.bullet.projection == f.bullet.projection);
    CHECK(e.bullet.stiffness == f.bullet.stiffness);
    CHECK(e.bullet.klst == f.bullet.klst);
    CHECK(e.bullet.repulsion_stiffness == f.bullet.repulsion_stiffness);
    CHECK(e.bullet.collision_margin == f.bullet.collision_margin);
    CHECK(e.self_collision == f.self_collision);
    CHECK(e.bullet.iterations == f.bullet.iterations);
  }
}

/// Grid indices (i, j) of the particles whose mask is exactly axes.
std::vector<std::pair<int, int>> held_with(const cloth::ClothParams& c,
                                           const std::vector<std::uint8_t>& mask,
                                           std::uint8_t axes) {
  std::vector<std::pair<int, int>> out;
  for (int j = 0; j < c.nv; ++j)
    for (int i = 0; i < c.nu; ++i)
      if (mask[static_cast<size_t>(cloth::particle_index(c, i, j))] == axes) out.emplace_back(i, j);
  return out;
}

using Pairs = std::vector<std::pair<int, int>>;

cloth::ClothParams grid(int nu, int nv, cloth::Plane plane = cloth::Plane::xz) {
  cloth::ClothParams c;
  c.nu = nu;
  c.nv = nv;
  c.size_u = nu - 1.0;  // 1 m spacing
  c.size_v = nv - 1.0;
  c.center = {0.0, 0.0, 0.0};
  c.plane = plane;
  return c;
}

ConstraintSpec select(const std::string& s, std::uint8_t hold = cloth::kHoldAll) {
  ConstraintSpec c;
  c.select = s;
  c.hold = hold;
  return c;
}

}  // namespace

TEST_CASE("every malformed scenario names its file, line, key and what was expected",
          "[scenario]") {
  const auto files = toml_files(kSource / "tests" / "data" / "bad");
  REQUIRE(files.size() >= 30);
  const std::regex expect("^# expect: (.+)\n# line: ([0-9]+)\n");
  for (const fs::path& file : files) {
    INFO(file.filename().string());
    const std::string text = read_file(file);
    std::smatch m;
    REQUIRE(std::regex_search(text, m, expect));
    const std::string message = error_of([&] { load_scenario(file.string()); });
    CHECK_THAT(message, Contains(m[1].str()));
    // the message starts with "<path>:<line>: "
    CHECK_THAT(message, Catch::StartsWith(file.string() + ":" + m[2].str() + ": "));
  }
}

TEST_CASE("structurally extreme TOML is refused before the parser sees it", "[scenario]") {
  // strings and comments do not count: brackets and dots in them are text
  const std::string text = "description = \"" + std::string(200, '[') + "\"  # " +
                           std::string(200, '{') + std::string(200, '.') + "\n[[engine]]\n";
  CHECK_FALSE(clothbench::toml_structure_problem(text));
  CHECK_NOTHROW(parse_scenario(text, "ok.toml"));
  // 64 levels are allowed, 65 are not; the line is named
  const auto nested = [](int depth) {
    return "\ngravity = " + std::string(size_t(depth), '[') + std::string(size_t(depth), ']');
  };
  CHECK_FALSE(clothbench::toml_structure_problem(nested(clothbench::kMaxTomlDepth)));
  const auto problem = clothbench::toml_structure_problem(nested(clothbench::kMaxTomlDepth + 1));
  REQUIRE(problem);
  CHECK(problem->first == 2);
  // a --set value is guarded alike
  CHECK_THAT(error_of([] { load_scenario(seed_path(), {"duration=" + std::string(100000, '[')}); }),
             Catch::StartsWith("--set duration: cannot read the value: arrays or inline tables "
                               "nested more than 64 deep"));
}

TEST_CASE("a --set value that is not valid UTF-8 is refused, not an internal error", "[scenario]") {
  // found by scripts/fuzz (tests/data/fuzz/overrides/): the bare-word fallback's parse threw
  const std::string bad = std::string("name=frampectkiur= ") + char(0x97) + "(";
  CHECK_THAT(error_of([&] { load_scenario(seed_path(), {bad}); }),
             Catch::StartsWith("--set name: cannot read the value as a string: "));
}

TEST_CASE("an unreadable scenario file is an error naming it", "[scenario]") {
  const std::string missing = (kSource / "tests" / "data" / "no_such_file.toml").string();
  CHECK(error_of([&] { load_scenario(missing); }) ==
        missing + ": cannot open the scenario file: No such file or directory");
  const std::string dir = (kSource / "tests" / "data").string();
  CHECK(error_of([&] { load_scenario(dir); }) ==
        dir + ": expected a scenario file, got a directory");
}

TEST_CASE("ScenarioError keeps where, key and problem apart", "[scenario]") {
  try {
    parse_scenario("duration = -1\n[[engine]]\n", "x.toml");
    FAIL("no error");
  } catch (const ScenarioError& e) {
    CHECK(e.where() == "x.toml:1");
    CHECK(e.key() == "duration");
    CHECK(e.problem() == "expected a number > 0, got -1");
    CHECK(std::string(e.what()) == "x.toml:1: duration: expected a number > 0, got -1");
  }
}

TEST_CASE("every shipped scenario loads, named after its file", "[scenario]") {
  const auto files = toml_files(kSource / "scenarios");
  std::vector<std::string> names;
  for (const fs::path& f : files) names.push_back(f.stem().string());
  CHECK(names == std::vector<std::string>{
                     "bullet_self_collision_demo", "cloth_pile", "curtain", "cusick_drape", "flag",
                     "flag_wind", "floor_drop", "free_fall", "garment", "hanging_chain", "incline",
                     "lift_corners", "napkin_fold", "seed_sphere_drape", "skirt", "sphere_sweep",
                     "table", "tablecloth", "towel_rail"});
  for (const fs::path& file : files) {
    INFO(file.filename().string());
    const Scenario s = load_scenario(file.string());
    CHECK(s.name == file.stem().string());
    CHECK(s.source == file.string());
    CHECK_FALSE(s.description.empty());
    REQUIRE_FALSE(s.engines.empty());
    CHECK(s.engines[static_cast<size_t>(s.reference_index())].name == s.reference);
    CHECK(s.scene.held.size() == static_cast<size_t>(s.scene.particle_count()));
    // the model the engines build accepts the scene
    CHECK_NOTHROW(cloth::build_model(s.scene));
  }
}

TEST_CASE("the example scenarios load", "[scenario]") {
  // examples/: scenes too long for the regression gate, run by hand or by a benchmark
  const Scenario s = load_scenario((kSource / "examples/large_steps/fabric_128.toml").string());
  CHECK(s.name == "fabric_128");
  CHECK(s.scene.particle_count() == 128 * 128);
  const cloth::Model m = cloth::build_model(s.scene);
  CHECK(m.mass.sum() == Approx(0.2).epsilon(1e-12));  // 1 m^2 of 200 g/m^2
}

TEST_CASE("shipped scenarios hold the particles their comments describe", "[scenario]") {
  const auto load = [](const char* name) {
    return load_scenario((kSource / "scenarios" / (std::string(name) + ".toml")).string());
  };
  SECTION("flag: the pole edge i = 0, pinned") {
    const Scenario s = load("flag");
    const auto& c = s.scene.cloth;
    Pairs pole;
    for (int j = 0; j < c.nv; ++j) pole.emplace_back(0, j);
    CHECK(held_with(c, s.scene.held, cloth::kHoldAll) == pole);
    CHECK(held_with(c, s.scene.held, 0).size() == static_cast<size_t>((c.nu - 1) * c.nv));
    CHECK(s.scene.spheres.empty());
  }
  SECTION("curtain: the top edge j = nv - 1, held in y and z, free along x") {
    const Scenario s = load("curtain");
    const auto& c = s.scene.cloth;
    CHECK(c.plane == cloth::Plane::xy);
    Pairs top;
    for (int i = 0; i < c.nu; ++i) top.emplace_back(i, c.nv - 1);
    CHECK(held_with(c, s.scene.held, cloth::kHoldY | cloth::kHoldZ) == top);
  }
  SECTION("table: nothing held, the cloth resting on the Cusick disk's contact shell") {
    const Scenario s = load("table");
    const auto& c = s.scene.cloth;
    CHECK(held_with(c, s.scene.held, 0).size() == static_cast<size_t>(s.scene.particle_count()));
    REQUIRE(s.scene.shapes.cylinders.size() == 1);
    const cloth::Cylinder& disk = s.scene.shapes.cylinders[0];
    CHECK(disk.radius == 0.15);
    CHECK(disk.center.y() + 0.5 * disk.height + disk.margin == Approx(c.center.y()));
  }
  SECTION("lift_corners: two corners of the edge j = 0 in a handle, nothing else held") {
    const Scenario s = load("lift_corners");
    const auto& c = s.scene.cloth;
    REQUIRE(s.scene.handles.size() == 1);
    CHECK(s.scene.handles[0].particles ==
          std::vector<int>{0, cloth::particle_index(c, c.nu - 1, 0)});
    CHECK(held_with(c, s.scene.held, 0).size() == static_cast<size_t>(s.scene.particle_count()));
  }
  SECTION("hanging_chain: a 1 x N chain of structural springs, the top particle pinned") {
    const Scenario s = load("hanging_chain");
    const auto& c = s.scene.cloth;
    CHECK(c.nu == 1);
    CHECK(c.k_shear == 0.0);
    CHECK(c.k_bend == 0.0);
    CHECK(held_with(c, s.scene.held, cloth::kHoldAll) == Pairs{{0, c.nv - 1}});
  }
  SECTION("free_fall: nothing held, nothing to hit") {
    const Scenario s = load("free_fall");
    CHECK(held_with(s.scene.cloth, s.scene.held, 0).size() ==
          static_cast<size_t>(s.scene.particle_count()));
    CHECK(s.scene.spheres.empty());
  }
  SECTION("sphere_sweep: the sphere moves") {
    const Scenario s = load("sphere_sweep");
    REQUIRE(s.scene.spheres.size() == 1);
    CHECK(s.scene.spheres[0].velocity.norm() > 0.0);
  }
}

TEST_CASE("the seed scenario is the engine's seed scene", "[scenario]") {
  const Scenario s = load_scenario(seed_path());
  check_same_scene(s.scene, cloth::seed_scene());
  CHECK(s.duration == 3.0);
  CHECK(s.frame_interval == 0.01);
  CHECK(s.snapshot_interval == 0.5);
  CHECK(s.animation_interval == Approx(0.03));  // 1/30 s rounded to 3 frames
  CHECK(s.reference == "custom-rk4");
  CHECK(s.reference_index() == 0);
  std::vector<std::string> names;
  for (const EngineSpec& e : s.engines) names.push_back(e.name);
  CHECK(names == std::vector<std::string>{"custom-rk4", "custom-symplectic-euler",
                                          "custom-midpoint", "custom-implicit-euler",
                                          "bullet-deformable-explicit",
                                          "bullet-deformable-implicit", "bullet-softbody-matched"});
  CHECK(s.engines[3].dt == 1e-3);
  CHECK(s.engines[5].bullet.implicit);
  CHECK(s.engines[6].bullet.stiffness == clothbench::reference::SoftbodyStiffness::matched);
}

TEST_CASE("keeping engines by name: a misspelt name is refused with the nearest one",
          "[scenario]") {
  try {
    load_scenario(seed_path(), {}, {"custom-midpiont"});
    FAIL("expected a ScenarioError");
  } catch (const ScenarioError& e) {
    CHECK_THAT(e.what(), Catch::Contains("custom-midpiont") && Catch::Contains("custom-midpoint"));
  }
}

TEST_CASE("the embedded default is scenarios/seed_sphere_drape.toml, byte for byte", "[scenario]") {
  const std::string file = read_file(seed_path());
  REQUIRE_FALSE(file.empty());
  CHECK(embedded_default_scenario() == file);
  const Scenario s = parse_scenario(embedded_default_scenario(), "<embedded>");
  CHECK(s.source == "<embedded>");
  check_same_scene(s.scene, cloth::seed_scene());
}

TEST_CASE("omitted keys take the struct defaults", "[scenario]") {
  const Scenario s = load_scenario((kSource / "tests/data/good/minimal.toml").string());
  const Scenario defaults;
  cloth::Scene scene;
  scene.held.assign(static_cast<size_t>(scene.particle_count()), 0);
  check_same_scene(s.scene, scene);
  CHECK(s.name == defaults.name);
  CHECK(s.duration == defaults.duration);
  CHECK(s.snapshot_interval == defaults.snapshot_interval);
  REQUIRE(s.engines.size() == 1);
  // an unnamed engine is named after its kind and integrator, and is the reference
  CHECK(s.engines[0].name == "custom-rk4");
  CHECK(s.engines[0].dt == EngineSpec{}.dt);
  CHECK(s.reference == "custom-rk4");
}

TEST_CASE("a stiffness table lists the spring kinds there are", "[scenario]") {
  const Scenario s =
      parse_scenario("[cloth]\nstiffness = { structural = 10.0 }\n[[engine]]\n", "partial.toml");
  CHECK(s.scene.cloth.k_structural == 10.0);
  CHECK(s.scene.cloth.k_shear == 0.0);
  CHECK(s.scene.cloth.k_bend == 0.0);
}

TEST_CASE("overrides given with --set reach any key before validation", "[scenario]") {
  const Scenario base = load_scenario(seed_path());
  SECTION("numbers, arrays, bare words and quoted strings") {
    const Scenario s = load_scenario(
        seed_path(), {"cloth.damping=0", "duration=0.5", "cloth.particles=[9,9]",
                      "engine.custom-rk4.dt=2e-4", "sphere.0.radius=0.5", "constraint.0.hold=y",
                      "cloth.plane=\"xy\"", "engine.1.integrator=explicit-euler"});
    CHECK(s.scene.cloth.damping == 0.0);
    CHECK(s.duration == 0.5);
    CHECK(s.scene.cloth.nu == 9);
    CHECK(s.scene.cloth.nv == 9);
    CHECK(s.engines[0].dt == 2e-4);
    CHECK(s.scene.spheres[0].radius == 0.5);
    CHECK(s.constraints[0].hold == cloth::kHoldY);
    CHECK(s.scene.cloth.plane == cloth::Plane::xy);
    CHECK(s.engines[1].solver.integrator == cloth::Integrator::explicit_euler);
    // the held mask follows the new grid
    CHECK(held_with(s.scene.cloth, s.scene.held, cloth::kHoldY) ==
          Pairs{{0, 0}, {8, 0}, {0, 8}, {8, 8}});
    // untouched keys keep the file's values
    CHECK(s.scene.cloth.k_bend == base.scene.cloth.k_bend);
    CHECK(s.engines[2].dt == base.engines[2].dt);
  }
  SECTION("the last override of a key wins") {
    const Scenario s = load_scenario(seed_path(), {"cloth.damping=1", "cloth.damping=2"});
    CHECK(s.scene.cloth.damping == 2.0);
  }
  SECTION("one stiffness kind") {
    // bullet-deformable has one stiffness for structural and shear springs: the engines kept
    // must model the scene, the others may be left out
    CHECK_THROWS_WITH(load_scenario(seed_path(), {"cloth.stiffness.shear=5"}),
                      Catch::Contains("bullet-deformable cannot model this scene"));
    const Scenario s = load_scenario(seed_path(), {"cloth.stiffness.shear=5"},
                                     {"custom-midpoint", "bullet-softbody-matched"});
    REQUIRE(s.engines.size() == 3);
    CHECK(s.engines[0].name == "custom-rk4");  // the reference stays
    CHECK(s.engines[1].name == "custom-midpoint");
    CHECK(s.engines[2].name == "bullet-softbody-matched");
    CHECK(s.scene.cloth.k_shear == 5.0);
    CHECK(s.scene.cloth.k_structural == base.scene.cloth.k_structural);
    // with no stiffness table in the file, the others keep their defaults
    const Scenario m = load_scenario((kSource / "tests/data/good/minimal.toml").string(),
                                     {"cloth.stiffness.bend=7"});
    CHECK(m.scene.cloth.k_bend == 7.0);
    CHECK(m.scene.cloth.k_structural == cloth::ClothParams{}.k_structural);
    CHECK(m.scene.cloth.k_shear == cloth::ClothParams{}.k_shear);
  }
  SECTION("total_mass replaces particle_mass") {
    const Scenario s = load_scenario(seed_path(), {"cloth.total_mass=62.5"});
    CHECK(s.scene.cloth.total_mass == 62.5);
  }
  SECTION("whole tables and lists") {
    const Scenario s =
        load_scenario(seed_path(), {"sphere=[]", "constraint.0={select=\"edge:v0\"}"});
    CHECK(s.scene.spheres.empty());
    CHECK(s.constraints[0].select == "edge:v0");
    CHECK(s.constraints[0].hold == cloth::kHoldAll);
  }
}

TEST_CASE("a bad --set override is an error naming the override", "[scenario]") {
  CHECK(set_error({"cloth.damping=-1"}) == "--set cloth.damping: expected a number >= 0, got -1");
  CHECK(set_error({"cloth.dampin=0"}) ==
        "--set cloth.dampin: unknown key \"dampin\" in cloth; did you mean \"damping\"?");
  CHECK(set_error({"duraton=1"}) ==
        "--set duraton: unknown key \"duraton\"; did you mean \"duration\"?");
  CHECK(set_error({"engine.custom-rk5.dt=1e-4"}) ==
        "--set engine.custom-rk5.dt: no engine named \"custom-rk5\"; did you mean \"custom-rk4\"?");
  CHECK(set_error({"engine.custom-rk4.dtt=1e-4"}) ==
        "--set engine.custom-rk4.dtt: unknown key \"dtt\" in engine.custom-rk4; did you mean "
        "\"dt\"?");
  CHECK(set_error({"sphere.3.radius=1"}) ==
        "--set sphere.3.radius: no sphere 3: the scenario has 1 [[sphere]], counted from 0");
  CHECK(set_error({"constraint.0.hold=xw"}) ==
        "--set constraint.0.hold: expected a non-empty combination of the letters x, y and z, "
        "got \"xw\"");
  CHECK(set_error({"engine.custom-rk4.klst=0.5"}) ==
        "--set engine.custom-rk4.klst: applies only to bullet-softbody engines, this one is "
        "custom");
  CHECK(set_error({"cloth.damping"}) ==
        "--set cloth.damping: expected KEY=VALUE, e.g. --set cloth.damping=0");
  CHECK(set_error({"cloth.damping="}) == "--set cloth.damping: expected a value after '='");
  CHECK(set_error({"duration.x=1"}) ==
        "--set duration.x: duration is a single value, it has no keys");
  CHECK(set_error({"cloth.stiffness.bend.x=1"}) ==
        "--set cloth.stiffness.bend.x: cloth.stiffness.bend is a single value, it has no keys");
  CHECK(set_error({"=1"}) == "--set =1: expected a key before '='");
  // a key the file gives becomes wrong through an overridden one: both are named
  CHECK_THAT(set_error({"engine.0.kind=bullet-softbody"}),
             Catch::EndsWith(":45: engine.custom-rk4.integrator: applies only to custom engines, "
                             "this one is bullet-softbody (--set engine.0.kind)"));
  CHECK_THAT(set_error({"cloth.particles=[9,9"}),
             Catch::StartsWith("--set cloth.particles: cannot read the value [9,9 as TOML"));
  // an inline table names the override and the key inside it
  CHECK(set_error({"cloth.stiffness={structural=1,sheer=2}"}) ==
        "--set cloth.stiffness: cloth.stiffness.sheer: unknown key; did you mean \"shear\"?");
  // relations between keys blame the overridden one
  CHECK_THAT(set_error({"engine.custom-rk4.dt=3e-4"}),
             Catch::StartsWith("--set engine.custom-rk4.dt: expected frame_interval to be a "
                               "whole multiple of dt"));
  CHECK(set_error({"frame_interval=0.0002"}) ==
        "--set frame_interval: expected frame_interval to be a whole multiple of dt, got "
        "frame_interval = 0.0002 s and dt = 0.001 s");
  CHECK_THAT(set_error({"snapshot_interval=0.015"}),
             Catch::StartsWith("--set snapshot_interval: expected snapshot_interval to be 0 or"));
  CHECK_THAT(
      set_error({"cloth.particle_mass=1", "cloth.total_mass=0"}),
      Catch::StartsWith("--set cloth.total_mass: expected a number from 1e-9 to 1e6, got 0"));
}

TEST_CASE("an engine that cannot model the scene is named with the feature", "[scenario]") {
  const std::string text =
      "frame_interval = 0.01\n"
      "[cloth]\n"
      "stiffness = { structural = 100.0, shear = 100.0, bend = 1.0 }\n"
      "[[engine]]\n"
      "name = \"def\"\n"
      "kind = \"bullet-deformable\"\n";
  CHECK_NOTHROW(parse_scenario(text, "ok.toml"));
  const std::string message =
      error_of([&] { parse_scenario(text, "x.toml", {"cloth.stiffness.shear=50"}); });
  CHECK_THAT(message, Catch::StartsWith("--set cloth.stiffness.shear: bullet-deformable cannot "
                                        "model this scene"));
  CHECK_THAT(message, Contains("one stiffness for structural and shear springs"));
}

TEST_CASE("scenario_to_toml gives back the same scenario", "[scenario]") {
  std::vector<fs::path> files = toml_files(kSource / "scenarios");
  for (const fs::path& f : toml_files(kSource / "tests" / "data" / "good")) files.push_back(f);
  for (const fs::path& file : files) {
    INFO(file.filename().string());
    const Scenario s = load_scenario(file.string());
    const std::string resolved = scenario_to_toml(s);
    const Scenario back = parse_scenario(resolved, "resolved.toml");
    check_same_scenario(s, back);
    CHECK(scenario_to_toml(back) == resolved);
  }
  SECTION("doubles are written exactly") {
    Scenario s = load_scenario(seed_path());
    s.scene.cloth.damping = 1.0 / 3.0;
    s.scene.gravity.y() = -9.80665;
    s.scene.spheres[0].margin = 1e-17;
    s.description = "line\nbreak \"quoted\" \\ \x01";
    const Scenario back = parse_scenario(scenario_to_toml(s), "resolved.toml");
    check_same_scenario(s, back);
  }
  SECTION("overrides are part of the resolved scenario") {
    const Scenario s = load_scenario(seed_path(), {"cloth.damping=12.5", "engine.2.dt=5e-4"});
    const std::string resolved = scenario_to_toml(s);
    CHECK_THAT(resolved, Contains("damping = 12.5"));
    check_same_scenario(s, parse_scenario(resolved, "resolved.toml"));
  }
}

/// A scene whose cloth is the grid c.
cloth::Scene scene_of(const cloth::ClothParams& c) {
  cloth::Scene s;
  s.cloth = c;
  return s;
}

TEST_CASE("held_mask selects corners, edges, disks and indices", "[scenario]") {
  const cloth::ClothParams c = grid(4, 3);
  const auto only = [&](const ConstraintSpec& k) {
    return held_with(c, held_mask(scene_of(c), {k}), k.hold);
  };
  CHECK(held_mask(scene_of(c), {}) == std::vector<std::uint8_t>(12, 0));
  CHECK(only(select("corners")) == Pairs{{0, 0}, {3, 0}, {0, 2}, {3, 2}});
  CHECK(only(select("edge:u0")) == Pairs{{0, 0}, {0, 1}, {0, 2}});
  CHECK(only(select("edge:u1")) == Pairs{{3, 0}, {3, 1}, {3, 2}});
  CHECK(only(select("edge:v0")) == Pairs{{0, 0}, {1, 0}, {2, 0}, {3, 0}});
  CHECK(only(select("edge:v1")) == Pairs{{0, 2}, {1, 2}, {2, 2}, {3, 2}});
  ConstraintSpec idx = select("indices", cloth::kHoldX);
  idx.indices = {{2, 1}, {1, 2}};
  CHECK(only(idx) == Pairs{{2, 1}, {1, 2}});

  SECTION("several constraints OR their axes") {
    const auto mask = held_mask(
        scene_of(c), {select("corners", cloth::kHoldX), select("edge:v0", cloth::kHoldY)});
    CHECK(held_with(c, mask, cloth::kHoldX | cloth::kHoldY) == Pairs{{0, 0}, {3, 0}});
    CHECK(held_with(c, mask, cloth::kHoldX) == Pairs{{0, 2}, {3, 2}});
    CHECK(held_with(c, mask, cloth::kHoldY) == Pairs{{1, 0}, {2, 0}});
  }
  SECTION("a disk's centre is on the plane's two world axes") {
    // 1 m spacing centred on the origin: i = 0..3 at x = -1.5..1.5, j = 0..2 at -1..1
    ConstraintSpec disk = select("disk", cloth::kHoldY);
    disk.disk_center_x = 1.5;
    disk.disk_center_z = 1.0;
    disk.disk_radius = 1.0;  // inclusive: the two neighbours at exactly 1 m are in
    CHECK(only(disk) == Pairs{{3, 1}, {2, 2}, {3, 2}});
    // the same disk on a vertical cloth: (x, y), around the cloth's centre height
    cloth::ClothParams v = grid(4, 3, cloth::Plane::xy);
    v.center = {0.0, 2.0, 5.0};
    disk.disk_center_z = 3.0;
    CHECK(held_with(v, held_mask(scene_of(v), {disk}), cloth::kHoldY) ==
          Pairs{{3, 1}, {2, 2}, {3, 2}});
    disk.disk_center_z = 1.0;
    disk.disk_radius = 0.5;
    CHECK(held_with(v, held_mask(scene_of(v), {disk}), cloth::kHoldY) == Pairs{{3, 0}});
  }
  SECTION("a selection outside the grid is a programmer error") {
    ConstraintSpec bad = select("indices");
    bad.indices = {{4, 0}};
    CHECK_THROWS_AS(held_mask(scene_of(c), {bad}), std::invalid_argument);
    CHECK_THROWS_AS(held_mask(scene_of(c), {select("edge:w0")}), std::invalid_argument);
  }
}

TEST_CASE("reference_index finds the reference engine", "[scenario]") {
  Scenario s;
  s.engines.resize(3);
  s.engines[0].name = "a";
  s.engines[1].name = "b";
  s.engines[2].name = "c";
  CHECK(s.reference_index() == 0);
  s.reference = "c";
  CHECK(s.reference_index() == 2);
  s.reference = "d";
  CHECK_THROWS_AS(s.reference_index(), std::invalid_argument);
  s.engines.clear();
  CHECK_THROWS_AS(s.reference_index(), std::invalid_argument);
}

namespace {

/// A cantilever strip: 5 columns along x from -0.02 to 0.02 m, 2 across; held up to x <= hold.
std::string cantilever_text(const std::string& test, double hold = 0.001) {
  return "gravity = [0.0, -9.8, 0.0]\n"
         "[cloth]\nparticles = [5, 2]\nsize = [0.04, 0.01]\ncenter = [0.0, 0.5, 0.0]\n"
         "plane = \"xz\"\n"
         "[[constraint]]\nselect = \"box\"\nmin = [-1.0, 0.0, -1.0]\nmax = [" +
         std::to_string(hold) + ", 1.0, 1.0]\n" + test + "[[engine]]\nkind = \"custom\"\n";
}

}  // namespace

TEST_CASE("test table, cantilever: read, checked against the held platform, written back",
          "[scenario]") {
  const Scenario s =
      parse_scenario(cantilever_text("[test]\nkind = \"cantilever\"\nedge = 0.0\n"), "c.toml");
  CHECK(s.test.kind == "cantilever");
  CHECK(s.test.edge == 0.0);
  // the resolved scenario keeps the test
  const Scenario again = parse_scenario(scenario_to_toml(s), "again.toml");
  CHECK(again.test.kind == "cantilever");
  CHECK(again.test.edge == 0.0);
  // no [test]: none
  CHECK(parse_scenario(cantilever_text(""), "c.toml").test.kind.empty());
}

TEST_CASE("test table, drape: read with its held disk, written back without an edge",
          "[scenario]") {
  const std::string text =
      "gravity = [0.0, -9.8, 0.0]\n"
      "[cloth]\nparticles = [9, 9]\nsize = [0.3, 0.3]\ncenter = [0.0, 0.5, 0.0]\n"
      "plane = \"xz\"\n"
      "[[constraint]]\nselect = \"within\"\ncenter = [0.0, 0.5, 0.0]\nradius = 0.09\n"
      "[test]\nkind = \"drape\"\n[[engine]]\nkind = \"custom\"\n";
  const Scenario s = parse_scenario(text, "d.toml");
  CHECK(s.test.kind == "drape");
  const std::string written = scenario_to_toml(s);
  CHECK_THAT(written, Contains("kind = \"drape\"") && !Contains("edge ="));
  CHECK(parse_scenario(written, "again.toml").test.kind == "drape");
  // without gravity the specimen has no weight to drape by
  CHECK_THROWS_WITH(
      parse_scenario("gravity = [0.0, 0.0, 0.0]\n" + text.substr(text.find('\n') + 1), "d.toml"),
      Contains("gravity"));
}

TEST_CASE("test table: refusals name the key and say why", "[scenario]") {
  const auto message = [](const std::string& text) {
    try {
      parse_scenario(text, "c.toml");
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // a bias-extension needs its 45-degree lattice specimen
  CHECK_THAT(message(cantilever_text("[test]\nkind = \"bias-extension\"\n")),
             Contains("test.kind") && Contains("lattice = \"grid\""));
  // a drape needs a held disk (the box here is not one) and takes no edge
  CHECK_THAT(message(cantilever_text("[test]\nkind = \"drape\"\n")),
             Contains("test.kind") && Contains("within"));
  CHECK_THAT(message(cantilever_text("[test]\nkind = \"drape\"\nedge = 0.0\n")),
             Contains("test.edge") && Contains("no edge"));
  CHECK_THAT(message(cantilever_text("[test]\nkind = \"drape\"\nfit_strain = 0.1\n")),
             Contains("test.fit_strain") && Contains("no fit_strain"));
  CHECK_THAT(message(cantilever_text("[test]\nkind = \"cantilevr\"\n")), Contains("cantilever"));
  CHECK_THAT(message(cantilever_text("[test]\nedge = 0.0\n")), Contains("expected a kind"));
  // a particle on the platform that no constraint holds (the column at x = 0 is left free)
  CHECK_THAT(message(cantilever_text("[test]\nkind = \"cantilever\"\nedge = 0.005\n", -0.001)),
             Contains("test.edge") && Contains("particle (2, 0)"));
  // an edge beyond the tip leaves no overhang
  CHECK_THAT(message(cantilever_text("[test]\nkind = \"cantilever\"\nedge = 0.5\n", 1.0)),
             Contains("the overhang"));
  CHECK_THAT(message(cantilever_text("[test]\nkind = \"cantilever\"\nsize = 1\n")),
             Contains("unknown key"));
}

TEST_CASE("newton = trust-region takes line-search's defaults and refuses what it cannot do",
          "[scenario][trust-region]") {
  const std::string head =
      "[[engine]]\n"
      "name = \"tr\"\n"
      "kind = \"custom\"\n"
      "integrator = \"implicit-euler\"\n"
      "newton = \"trust-region\"\n";
  const Scenario s = parse_scenario(head + "contacts = \"barrier\"\n", "tr.toml");
  const cloth::SolverOptions& o = s.engines.at(0).solver;
  CHECK(o.newton == cloth::NewtonMethod::trust_region);
  CHECK(o.newton_iterations == cloth::kLineSearchNewtonIterations);
  CHECK(o.cg_forcing == cloth::CgForcing::adaptive);
  CHECK(o.contacts == cloth::ContactMode::barrier);
  // the written scenario reads back the same
  CHECK(parse_scenario(scenario_to_toml(s), "again.toml").engines.at(0).solver.newton ==
        cloth::NewtonMethod::trust_region);
  CHECK_THAT(error_of([&] { parse_scenario(head + "linear_solver = \"ldlt\"\n", "x.toml"); }),
             Contains("linear_solver") && Contains("trust-region"));
  CHECK_THAT(error_of([&] { parse_scenario(head + "clamped_iterations = 3\n", "x.toml"); }),
             Contains("clamped_iterations") && Contains("line-search"));
}

TEST_CASE(
    "implicit-euler's default is line-search with the barrier; other integrators keep "
    "linearized",
    "[scenario]") {
  const auto engine = [](const std::string& integrator) {
    return parse_scenario("[[engine]]\nkind = \"custom\"\nintegrator = \"" + integrator + "\"\n",
                          "e.toml")
        .engines.at(0)
        .solver;
  };
  const cloth::SolverOptions implicit = engine("implicit-euler");
  CHECK(implicit.newton == cloth::NewtonMethod::line_search);
  CHECK(implicit.contacts == cloth::ContactMode::barrier);
  CHECK(implicit.newton_iterations == cloth::kLineSearchNewtonIterations);
  CHECK(implicit.cg_tolerance == cloth::kLineSearchCgTolerance);
  CHECK(implicit.cg_forcing == cloth::CgForcing::adaptive);
  // the key is inert for another integrator, whose engine a sweep may turn into implicit-euler:
  // that one steps linearized, with contacts after the step
  const cloth::SolverOptions rk4 = engine("rk4");
  CHECK(rk4.newton == cloth::NewtonMethod::linearized);
  CHECK(rk4.contacts == cloth::ContactMode::after_step);
  CHECK(rk4.newton_iterations == 1);
  // named, linearized is Baraff and Witkin's single solve
  const cloth::SolverOptions named = parse_scenario(
                                         "[[engine]]\nkind = \"custom\"\nintegrator = "
                                         "\"implicit-euler\"\nnewton = \"linearized\"\n",
                                         "n.toml")
                                         .engines.at(0)
                                         .solver;
  CHECK(named.newton == cloth::NewtonMethod::linearized);
  CHECK(named.newton_iterations == 1);
  CHECK(named.contacts == cloth::ContactMode::after_step);
}

TEST_CASE("every shipped implicit-euler engine names the Newton method of its baseline",
          "[scenario]") {
  // a change of the default then moves no baseline (scenarios/, with its subfolders)
  int engines = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kSource / "scenarios")) {
    if (entry.path().extension() != ".toml") continue;
    // each engine's table: from its [[engine]] line to the next table
    const std::string t = read_file(entry.path());
    for (size_t at = t.find("[[engine]]"); at != std::string::npos;
         at = t.find("[[engine]]", at + 1)) {
      const size_t end = t.find("\n[", at + 1);
      const std::string table = t.substr(at, end == std::string::npos ? end : end - at);
      if (table.find("integrator = \"implicit-euler\"") == std::string::npos) continue;
      INFO(entry.path().string() << "\n" << table);
      CHECK(table.find("\nnewton = ") != std::string::npos);
      ++engines;
    }
  }
  CHECK(engines >= 20);
}
