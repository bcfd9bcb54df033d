// The hinge model's keys: cloth.bend_model and cloth.bending_rigidity, what each engine and
// integrator does with them, and that a written scenario reads back the same.

#include <catch2/catch.hpp>
#include <string>

#include "harness/scenario/scenario.hpp"
#include "harness/scenario/scenario_error.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_writer.hpp"

using namespace clothbench;
using Catch::Matchers::Contains;

namespace {

/// A small grid with the cloth keys extra and one engine given by its keys.
std::string hinge_scene(const std::string& extra, const std::string& engine) {
  return "duration = 0.01\n"
         "[cloth]\n"
         "particles = [4, 4]\n"
         "size = [0.3, 0.3]\n"
         "stiffness = { structural = 20.0, shear = 20.0 }\n" +
         extra + "[[engine]]\nname = \"e\"\n" + engine;
}

const std::string kHinge = "bend_model = \"hinge\"\nbending_rigidity = 1.4e-5\n";

}  // namespace

TEST_CASE("cloth.bend_model = hinge reads its rigidity and builds no bend springs", "[hinge]") {
  const Scenario s =
      parse_scenario(hinge_scene(kHinge, "kind = \"custom\"\nintegrator = \"rk4\"\n"), "x.toml");
  REQUIRE(s.scene.cloth.bend_model == cloth::BendModel::hinge);
  REQUIRE(s.scene.cloth.bending_rigidity == 1.4e-5);
  REQUIRE(s.scene.cloth.k_bend == 0.0);
  // the written scenario says the same
  const Scenario back = parse_scenario(scenario_to_toml(s), "back.toml");
  REQUIRE(back.scene.cloth.bend_model == cloth::BendModel::hinge);
  REQUIRE(back.scene.cloth.bending_rigidity == 1.4e-5);
}

TEST_CASE("the hinge model's keys are refused where they do not apply", "[hinge]") {
  const std::string custom = "kind = \"custom\"\nintegrator = \"rk4\"\n";
  REQUIRE_THROWS_WITH(parse_scenario(hinge_scene("bend_model = \"hinge\"\n", custom), "x.toml"),
                      Contains("cloth.bending_rigidity") && Contains("needs"));
  REQUIRE_THROWS_WITH(parse_scenario(hinge_scene("bending_rigidity = 1e-5\n", custom), "x.toml"),
                      Contains("applies to bend_model = \"hinge\""));
  REQUIRE_THROWS_WITH(
      parse_scenario(hinge_scene("bend_model = \"hinge\"\nbending_rigidity = 0.0\n", custom),
                     "x.toml"),
      Contains("cloth.bending_rigidity"));
  std::string with_bend = hinge_scene(kHinge, custom);
  with_bend.replace(with_bend.find("shear = 20.0 }"), 14, "shear = 20.0, bend = 2.0 }");
  REQUIRE_THROWS_WITH(parse_scenario(with_bend, "x.toml"),
                      Contains("cloth.stiffness.bend") && Contains("no bend springs"));
  REQUIRE_THROWS_WITH(parse_scenario(hinge_scene("bend_model = \"plate\"\n", custom), "x.toml"),
                      Contains("cloth.bend_model"));
}

TEST_CASE("xpbd, projective and the Bullet engines refuse the hinge model at load", "[hinge]") {
  const std::string engine = GENERATE(
      std::string("kind = \"custom\"\nintegrator = \"xpbd\"\n"),
      std::string("kind = \"custom\"\nintegrator = \"projective\"\n"),
      std::string("kind = \"bullet-deformable\"\n"), std::string("kind = \"bullet-softbody\"\n"));
  CAPTURE(engine);
  REQUIRE_THROWS_WITH(parse_scenario(hinge_scene(kHinge, engine), "x.toml"),
                      Contains("bend_model = \"hinge\""));
}

TEST_CASE("the explicit and implicit custom integrators accept the hinge model", "[hinge]") {
  const std::string integrator =
      GENERATE("symplectic-euler", "rk4", "implicit-euler", "imex-euler");
  CAPTURE(integrator);
  REQUIRE_NOTHROW(parse_scenario(
      hinge_scene(kHinge, "kind = \"custom\"\nintegrator = \"" + integrator + "\"\n"), "x.toml"));
}
