// The self-contact keys: the cloth's self_collision, thickness and self_friction, an engine's
// own self_collision, bullet-deformable's repulsion_stiffness and collision_margin, and what
// each engine kind does with them.

#include <catch2/catch.hpp>
#include <functional>
#include <regex>

#include "harness/engines/engine_factory.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario.hpp"
#include "harness/scenario/scenario_error.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_writer.hpp"

using namespace clothbench;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

/// A small grid with a custom, a bullet-deformable and a bullet-softbody engine; extra goes
/// into [cloth], engine_extra into every engine.
std::string three_engines(const std::string& extra, const std::string& softbody_extra = "") {
  return "frame_interval = 0.01\n"
         "duration = 0.01\n"
         "[cloth]\n"
         "particles = [4, 4]\n"
         "size = [0.3, 0.3]\n"
         "stiffness = { structural = 20.0, shear = 20.0, bend = 2.0 }\n" +
         extra +
         "[[engine]]\n"
         "name = \"c\"\n"
         "kind = \"custom\"\n"
         "[[engine]]\n"
         "name = \"d\"\n"
         "kind = \"bullet-deformable\"\n"
         "[[engine]]\n"
         "name = \"s\"\n"
         "kind = \"bullet-softbody\"\n" +
         softbody_extra;
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

SelfCollision of(const Scenario& s, int k) {
  return self_collision_of(s.engines[static_cast<size_t>(k)], s.scene.cloth);
}

}  // namespace

TEST_CASE("self-contact is off unless asked for, with the documented defaults",
          "[scenario][self-contact]") {
  const Scenario s = parse_scenario(three_engines(""), "x.toml");
  CHECK_FALSE(s.scene.cloth.self_collision);
  CHECK(s.scene.cloth.thickness == 0.004);
  CHECK(s.scene.cloth.self_friction == 0.0);
  for (int k = 0; k < 3; ++k) CHECK(of(s, k) == SelfCollision::off);
  CHECK(s.warnings.empty());
}

TEST_CASE("the cloth's self_collision reaches every engine that can do it",
          "[scenario][self-contact]") {
  const Scenario s = parse_scenario(
      three_engines("self_collision = true\nthickness = 0.002\nself_friction = 0.3\n"), "x.toml");
  CHECK(s.scene.cloth.thickness == 0.002);
  CHECK(s.scene.cloth.self_friction == 0.3);
  CHECK(of(s, 0) == SelfCollision::on);
  CHECK(of(s, 1) == SelfCollision::on);
  // inherited by bullet-softbody: noted, not refused
  CHECK(of(s, 2) == SelfCollision::not_available);
  REQUIRE(s.warnings.size() == 1);
  CHECK_THAT(s.warnings[0], StartsWith("engine s: cloth.self_collision = true is not available"));
  CHECK(std::string(self_collision_name(of(s, 2))) == "not available");
}

TEST_CASE("an engine's own self_collision overrides the cloth's", "[scenario][self-contact]") {
  const Scenario on = parse_scenario(three_engines("self_collision = true\n"), "x.toml",
                                     {"engine.c.self_collision=false"});
  CHECK(of(on, 0) == SelfCollision::off);
  CHECK(of(on, 1) == SelfCollision::on);
  const Scenario off =
      parse_scenario(three_engines(""), "x.toml", {"engine.d.self_collision=true"});
  CHECK(of(off, 0) == SelfCollision::off);
  CHECK(of(off, 1) == SelfCollision::on);
  // false on bullet-softbody is what it does anyway
  const Scenario sb = parse_scenario(
      three_engines("self_collision = true\n", "self_collision = false\n"), "x.toml");
  CHECK(of(sb, 2) == SelfCollision::off);
  CHECK(sb.warnings.empty());
}

TEST_CASE("an explicit self_collision = true on bullet-softbody is refused at its line",
          "[scenario][self-contact]") {
  const std::string message =
      error_of([&] { parse_scenario(three_engines("", "self_collision = true\n"), "x.toml"); });
  CHECK_THAT(message, StartsWith("x.toml:16: engine.s.self_collision: bullet-softbody cannot keep "
                                 "a cloth's layers apart"));
  const std::string set = error_of(
      [&] { parse_scenario(three_engines(""), "x.toml", {"engine.s.self_collision=true"}); });
  CHECK_THAT(set, StartsWith("--set engine.s.self_collision: bullet-softbody cannot"));
}

TEST_CASE("bullet-deformable's repulsion keys are its own and checked",
          "[scenario][self-contact]") {
  const Scenario s =
      parse_scenario(three_engines(""), "x.toml",
                     {"engine.d.repulsion_stiffness=4", "engine.d.collision_margin=0.02"});
  CHECK(s.engines[1].bullet.repulsion_stiffness == 4.0);
  CHECK(s.engines[1].bullet.collision_margin == 0.02);
  CHECK_THAT(error_of([&] {
               parse_scenario(three_engines(""), "x.toml", {"engine.c.repulsion_stiffness=4"});
             }),
             Contains("applies only to bullet-deformable engines"));
  CHECK_THAT(error_of([&] {
               parse_scenario(three_engines(""), "x.toml", {"engine.d.repulsion_stiffness=0"});
             }),
             Contains("repulsion_stiffness"));
  CHECK_THAT(error_of([&] { parse_scenario(three_engines("thickness = 0.0\n"), "x.toml"); }),
             Contains("cloth.thickness"));
  CHECK_THAT(error_of([&] { parse_scenario(three_engines("self_friction = -1.0\n"), "x.toml"); }),
             Contains("cloth.self_friction"));
}

TEST_CASE("the resolved scenario keeps the self-contact keys", "[scenario][self-contact]") {
  const Scenario s =
      parse_scenario(three_engines("self_collision = true\nthickness = 0.003\n"), "x.toml",
                     {"engine.c.self_collision=false", "engine.d.collision_margin=0.001"});
  const Scenario back = parse_scenario(scenario_to_toml(s), "resolved.toml");
  CHECK(back.scene.cloth.self_collision);
  CHECK(back.scene.cloth.thickness == 0.003);
  CHECK(back.engines[0].self_collision == std::optional<bool>(false));
  CHECK_FALSE(back.engines[1].self_collision.has_value());
  CHECK(back.engines[1].bullet.collision_margin == 0.001);
  CHECK(of(back, 2) == SelfCollision::not_available);
}

TEST_CASE("the same fold with and without the engine-level override", "[runner][self-contact]") {
  // a 9 x 9 napkin (2 cm spacing, no bend springs) on the floor; its edge j = 0 carried over the
  // opposite edge
  // on a half circle and laid down 1 cm above the floor's shell (2.5 thicknesses)
  const std::string text =
      "duration = 2.5\n"
      "frame_interval = 0.01\n"
      "[cloth]\n"
      "particles = [9, 9]\n"
      "size = [0.16, 0.16]\n"
      "center = [0.0, 0.01, 0.0]\n"
      "total_mass = 0.00512\n"
      "stiffness = { structural = 50.0, shear = 50.0 }\n"
      "damping = 0.01\n"
      "air_drag = 0.0002\n"
      "self_collision = true\n"
      "thickness = 0.004\n"
      "[[plane]]\n"
      "normal = [0.0, 1.0, 0.0]\n"
      "friction = 0.5\n"
      "[[handle]]\n"
      "select = \"edge:v0\"\n"
      "path = [[0.0, 0.0, 0.0, 0.0], [0.4, 0.0, 0.047, 0.015], [0.8, 0.0, 0.076, 0.055],\n"
      "        [1.2, 0.0, 0.076, 0.105], [1.6, 0.0, 0.047, 0.145], [2.0, 0.0, 0.01, 0.16]]\n"
      "[[engine]]\n"
      "name = \"on\"\n"
      "kind = \"custom\"\n"
      "integrator = \"symplectic-euler\"\n"
      "dt = 5e-4\n"
      "[[engine]]\n"
      "name = \"off\"\n"
      "kind = \"custom\"\n"
      "integrator = \"symplectic-euler\"\n"
      "dt = 5e-4\n"
      "self_collision = false\n";
  const Scenario s = parse_scenario(text, "fold.toml");
  RunOptions o;
  o.progress = false;
  const RunResult r = run_scenario(s, o);
  REQUIRE(r.runs.size() == 2);
  const double thickness = s.scene.cloth.thickness;
  // with self-contact: no frame crosses or touches, and the layers end about a thickness apart
  double on_gap = 1.0;
  for (const FrameMetrics& m : r.runs[0].frames) {
    REQUIRE(m.self_intersections == 0);
    on_gap = std::min(on_gap, m.min_self_distance);
  }
  int off_crossings = 0;
  for (const FrameMetrics& m : r.runs[1].frames)
    off_crossings = std::max(off_crossings, m.self_intersections);
  CHECK(r.runs[0].stable);
  CHECK(on_gap > 0.5 * thickness);
  // without it the folded layer (no bend springs to hold it up) falls through the one below
  CHECK(off_crossings > 0);
}

TEST_CASE("bullet-deformable's margin check reads the engine's own self_collision",
          "[scenario][self-contact]") {
  // a floor of margin 0.01 m and a thickness of 0.004 m: Bullet's one margin cannot be both
  const std::string floor = "self_collision = true\n[[plane]]\nnormal = [0.0, 1.0, 0.0]\n";
  CHECK_THAT(error_of([&] { parse_scenario(three_engines(floor), "x.toml"); }),
             Contains("share the soft body's one collision margin"));
  // without self-collision in that engine the margins do not meet
  CHECK_NOTHROW(parse_scenario(three_engines(floor), "x.toml", {"engine.d.self_collision=false"}));
  // equal margins: accepted with it on
  CHECK_NOTHROW(parse_scenario(three_engines(floor), "x.toml", {"cloth.thickness=0.02"}));
}

TEST_CASE("a thickness the rest shape already violates is refused, naming both elements",
          "[scenario][self-contact]") {
  // 4 x 4 particles 0.1 m apart, triangles split along (i, j) - (i + 1, j + 1): particle (3, 1)
  // is three rings from the triangle (1, 2), (2, 3), (1, 3) and 0.3 / sqrt(2) = 0.212 m from
  // its edge (1, 2) - (2, 3); the grid's symmetry puts other pairs at the same distance (such as
  // (2, 1) and (0, 2), (1, 3), (0, 3)), and round-off decides which of them is found first
  const std::string text = three_engines("self_collision = true\nthickness = 0.25\n");
  const std::string message = error_of([&] { parse_scenario(text, "x.toml"); });
  const std::regex expected(
      "x\\.toml:8: cloth\\.thickness: self-contact keeps layers 0\\.25 m apart, but at rest "
      "particle \\(\\d, \\d\\) and the triangle \\(\\d, \\d\\), \\(\\d, \\d\\), "
      "\\(\\d, \\d\\) are already 0\\.212 m apart \\(more than two rings apart\\): give a "
      "thickness below that, or a mesh whose edges are longer than about twice the thickness");
  INFO(message);
  CHECK(std::regex_match(message, expected));
  // the same thickness with self-contact off in every engine is no contact at all
  CHECK_NOTHROW(parse_scenario(three_engines("thickness = 0.25\n"), "x.toml"));
  CHECK_NOTHROW(
      parse_scenario(three_engines("self_collision = true\nthickness = 0.2\n"), "x.toml"));
}
