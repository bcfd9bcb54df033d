// [[engine]] overrides = { "key.path" = value }: an engine's own scene keys, applied for that
// engine alone; what the loader refuses, what the writer keeps, and that an engine with
// overrides runs exactly the scene a file with those values gives.

#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "harness/run/engine_metric.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario.hpp"
#include "harness/scenario/scenario_error.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_writer.hpp"

using namespace clothbench;
using Catch::Matchers::Contains;

namespace {

/// A small hanging grid, bend stiffness bend, with two rk4 engines a and b; b's table gets
/// b_keys.
std::string two_engines(const std::string& bend, const std::string& b_keys) {
  return "duration = 0.2\n"
         "frame_interval = 0.01\n"
         "[cloth]\n"
         "particles = [5, 5]\n"
         "size = [0.4, 0.4]\n"
         "stiffness = { structural = 200.0, shear = 200.0, bend = " +
         bend +
         " }\n"
         "damping = 0.05\n"
         "[[constraint]]\nselect = \"corners\"\n"
         "[[engine]]\nname = \"a\"\nkind = \"custom\"\nintegrator = \"rk4\"\ndt = 1e-3\n"
         "[[engine]]\nname = \"b\"\nkind = \"custom\"\nintegrator = \"rk4\"\ndt = 1e-3\n" +
         b_keys;
}

/// The message parse_scenario gives for text, or "" when it loads.
std::string error_of(const std::string& text) {
  try {
    parse_scenario(text, "x.toml");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("an engine's overrides change its scene alone", "[scenario][overrides]") {
  const std::string keys = GENERATE(std::string("overrides = { \"cloth.stiffness.bend\" = 7.5 }\n"),
                                    std::string("overrides = { cloth.stiffness.bend = 7.5 }\n"));
  const Scenario s = parse_scenario(two_engines("50.0", keys), "x.toml");
  REQUIRE(s.engines[0].overrides.empty());
  REQUIRE(!s.engines[0].scene);
  REQUIRE(engine_scene(s, s.engines[0]).cloth.k_bend == 50.0);
  REQUIRE(s.engines[1].overrides.size() == 1);
  REQUIRE(s.engines[1].overrides[0].first == "cloth.stiffness.bend");
  REQUIRE(engine_scene(s, s.engines[1]).cloth.k_bend == 7.5);
  // everything else of b's scene is the scenario's
  REQUIRE(engine_scene(s, s.engines[1]).cloth.k_structural == 200.0);
  REQUIRE(engine_scene(s, s.engines[1]).held == s.scene.held);
  // the written scenario (a run's copy) reads back with the same overrides
  const Scenario back = parse_scenario(scenario_to_toml(s), "back.toml");
  REQUIRE(back.engines[1].overrides == s.engines[1].overrides);
  REQUIRE(engine_scene(back, back.engines[1]).cloth.k_bend == 7.5);
  REQUIRE(!back.engines[0].scene);
}

TEST_CASE("an engine's overrides are refused naming the engine and the key",
          "[scenario][overrides]") {
  // an engine key belongs in the engine's table
  CHECK_THAT(error_of(two_engines("50.0", "overrides = { \"engine.b.dt\" = 2e-3 }\n")),
             Contains("engine.b.overrides") && Contains("engine's own keys"));
  // a run setting or a constraint is the same for every engine
  CHECK_THAT(error_of(two_engines("50.0", "overrides = { duration = 1.0 }\n")),
             Contains("engine.b.overrides") && Contains("physics only"));
  CHECK_THAT(
      error_of(two_engines("50.0", "overrides = { \"constraint.0.select\" = \"indices\" }\n")),
      Contains("physics only"));
  // an unknown key, with its suggestion
  CHECK_THAT(error_of(two_engines("50.0", "overrides = { \"cloth.stiffness.bnd\" = 1.0 }\n")),
             Contains("engine.b.overrides") && Contains("bnd") && Contains("bend"));
  // a value the key refuses, found when the engine's scene is read
  CHECK_THAT(error_of(two_engines("50.0", "overrides = { \"cloth.damping\" = -1.0 }\n")),
             Contains("engine.b.overrides") && Contains("cloth.damping") && Contains(">= 0"));
  // another rest shape is another scene, not another material
  CHECK_THAT(error_of(two_engines("50.0", "overrides = { \"cloth.particles\" = [6, 6] }\n")),
             Contains("engine.b.overrides") && Contains("rest shape"));
  // not a table
  CHECK_THAT(error_of(two_engines("50.0", "overrides = 3\n")),
             Contains("engine.b.overrides") && Contains("expected a table"));
}

TEST_CASE("an engine with overrides runs the scene a file with those values gives",
          "[runner][overrides]") {
  const Scenario mixed = parse_scenario(
      two_engines("50.0", "overrides = { \"cloth.stiffness.bend\" = 7.5 }\n"), "mixed.toml");
  const Scenario plain = parse_scenario(two_engines("7.5", ""), "plain.toml");
  RunOptions o;
  o.progress = false;
  const RunResult m = run_scenario(mixed, o);
  const RunResult p = run_scenario(plain, o);
  // b with its override steps exactly as b in the file that says 7.5, energies included
  const EngineRun& mb = m.runs[1];
  const EngineRun& pb = p.runs[1];
  REQUIRE(mb.frames.size() == pb.frames.size());
  REQUIRE(mb.snapshots.back() == pb.snapshots.back());
  REQUIRE(mb.frames.back().elastic_potential == pb.frames.back().elastic_potential);
  // and a, without overrides, runs the file's 50 N/m: a different shape
  REQUIRE(m.runs[0].snapshots.back() != mb.snapshots.back());
}

TEST_CASE("an engine with overrides is measured in its own springs", "[runner][overrides]") {
  // the strip-tensile force comes from the springs: an engine's own, not the file's
  const std::string path = CLOTHBENCH_SOURCE_DIR "/scenarios/fabric/strip-tensile-warp.toml";
  const auto tensile = [&](const std::string& set) {
    std::vector<std::string> sets = {"duration=1.5"};  // past fit_strain = 1 %
    if (!set.empty()) sets.push_back(set);
    Scenario sc = load_scenario(path, sets, {"custom-implicit-euler"});
    sc.engines.erase(sc.engines.begin());  // the reference, symplectic Euler at 4e-5 s
    sc.reference = sc.engines.front().name;
    RunOptions o;
    o.progress = false;
    const RunResult r = run_scenario(sc, o);
    return engine_metric(r, r.runs.front(), "tensile_stiffness").value_or(NAN);
  };
  const double own = tensile(
      "engine.custom-implicit-euler.overrides={ \"cloth.stiffness.structural_u\" = 4000.0 }");
  const double file = tensile("cloth.stiffness.structural_u=4000.0");
  const double base = tensile("");
  CAPTURE(own, file, base);
  REQUIRE(std::isfinite(own));
  REQUIRE(own == file);
  REQUIRE(own > base);
}
