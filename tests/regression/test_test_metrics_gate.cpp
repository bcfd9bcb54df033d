// The gate on the [test] metrics (tests.csv): hand-made baselines and measurements, no
// recorded engine output.

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "harness/gate/test_metrics_gate.hpp"
#include "harness/io/user_error.hpp"
#include "temp_dir.hpp"

using namespace clothbench;
using Catch::Matchers::Contains;

namespace {

/// Tolerances of two metrics: bending_length 1 % relative, chord_angle 0.05 absolute.
Tolerances two_metrics() {
  Tolerances t;
  t.tests = {{"bending_length", {0.0, 0.01}}, {"chord_angle", {0.05, 0.0}}};
  return t;
}

const Tolerances kTol = two_metrics();

/// The one gate of engine e and quantity q.
const Gate& gate_of(const std::vector<Gate>& gates, const std::string& e, const std::string& q) {
  for (const Gate& g : gates)
    if (g.engine == e && g.quantity == q) return g;
  FAIL("no gate " << e << " " << q);
  return gates.front();
}

bool all_pass(const std::vector<Gate>& gates) {
  for (const Gate& g : gates)
    if (!g.pass) return false;
  return true;
}

}  // namespace

TEST_CASE("test metrics gate: an unmoved metric passes, a moved one fails with its numbers",
          "[regression]") {
  const TestValues base = {{"a", {{"bending_length", 0.05}, {"chord_angle", 41.0}}}};
  SECTION("within the tolerance on both metrics") {
    // 0.05 * 1.009 moves by 0.9 % of 1 % allowed; 41.04 by 0.04 of 0.05
    const TestValues now = {{"a", {{"bending_length", 0.05 * 1.009}, {"chord_angle", 41.04}}}};
    const std::vector<Gate> gates = gate_test_metrics("s", base, now, kTol, false);
    REQUIRE(gates.size() == 2);
    REQUIRE(all_pass(gates));
  }
  SECTION("bending_length moved by 1.1 % of an allowed 1 %") {
    const TestValues now = {{"a", {{"bending_length", 0.05 * 1.011}, {"chord_angle", 41.0}}}};
    const std::vector<Gate> gates = gate_test_metrics("s", base, now, kTol, false);
    const Gate& g = gate_of(gates, "a", "test.bending_length");
    REQUIRE_FALSE(g.pass);
    REQUIRE(g.note == "moved");
    REQUIRE(g.baseline == 0.05);
    REQUIRE(g.now == 0.05 * 1.011);
    REQUIRE(g.allowed == Approx(0.0005));
    REQUIRE(g.difference == Approx(0.00055));
    REQUIRE(gate_of(gates, "a", "test.chord_angle").pass);
    // the printed line names the metric, the engine, both values and the allowance
    const std::string line = format_gates({g});
    REQUIRE_THAT(line, Contains("test.bending_length") && Contains("0.05055") &&
                           Contains("0.0005") && Contains("FAIL: moved"));
  }
}

TEST_CASE("test metrics gate: undefined values, missing rows and metrics without tolerance",
          "[regression]") {
  const TestValues base = {{"a", {{"bending_length", NAN}, {"chord_angle", 41.0}}},
                           {"gone", {{"chord_angle", 40.0}}}};
  const TestValues now = {{"a", {{"bending_length", NAN}, {"chord_angle", NAN}, {"folds", 6.0}}},
                          {"new", {{"chord_angle", 40.0}}}};
  const std::vector<Gate> gates = gate_test_metrics("s", base, now, kTol, false);
  // undefined on both sides is the same result; on one side a change
  REQUIRE(gate_of(gates, "a", "test.bending_length").pass);
  REQUIRE_FALSE(gate_of(gates, "a", "test.chord_angle").pass);
  REQUIRE_THAT(gate_of(gates, "a", "test.chord_angle").note, Contains("undefined"));
  // a metric measured now but not recorded, and without a tolerance
  REQUIRE_FALSE(gate_of(gates, "a", "test.folds").pass);
  REQUIRE_THAT(gate_of(gates, "a", "test.folds").note, Contains("not in the baseline"));
  // engines on one side only fail once each
  REQUIRE_FALSE(gate_of(gates, "gone", "test metrics").pass);
  REQUIRE_FALSE(gate_of(gates, "new", "test metrics").pass);
  REQUIRE(gates.size() == 5);
  SECTION("a recorded metric no longer measured, and one with no tolerance") {
    const TestValues b2 = {{"a", {{"chord_angle", 41.0}, {"folds", 6.0}}}};
    const TestValues n2 = {{"a", {{"chord_angle", 41.0}, {"tip_deflection", 0.02}}}};
    const TestValues b3 = {{"a", {{"chord_angle", 41.0}, {"tip_deflection", 0.02}}}};
    const std::vector<Gate> g2 = gate_test_metrics("s", b2, n2, kTol, false);
    REQUIRE_THAT(gate_of(g2, "a", "test.folds").note, Contains("not measured"));
    const std::vector<Gate> g3 = gate_test_metrics("s", b3, n2, kTol, false);
    REQUIRE_FALSE(gate_of(g3, "a", "test.tip_deflection").pass);
    REQUIRE_THAT(gate_of(g3, "a", "test.tip_deflection").note,
                 Contains("no tolerance") && Contains("[tests]"));
    REQUIRE(gate_of(g3, "a", "test.chord_angle").pass);
  }
}

TEST_CASE("test metrics gate: a metric ungated for one engine is shown with its reason",
          "[regression]") {
  Tolerances t = two_metrics();
  t.ungated["chaotic"]["test.chord_angle"] = "contacts flip";
  const TestValues base = {{"chaotic", {{"chord_angle", 41.0}}}, {"a", {{"chord_angle", 41.0}}}};
  const TestValues now = {{"chaotic", {{"chord_angle", 45.0}}}, {"a", {{"chord_angle", 45.0}}}};
  const std::vector<Gate> gates = gate_test_metrics("s", base, now, t, false);
  const Gate& shown = gate_of(gates, "chaotic", "test.chord_angle");
  REQUIRE_FALSE(shown.gated);
  REQUIRE(shown.pass);
  REQUIRE_THAT(shown.note, Contains("not gated: contacts flip"));
  // the other engine's move is still gated
  REQUIRE_FALSE(gate_of(gates, "a", "test.chord_angle").pass);
}

TEST_CASE(
    "test metrics gate: a metric an ensemble gates is left to it, or shown when it did not run",
    "[regression]") {
  Tolerances t = two_metrics();
  t.ensemble["chaotic"].quantities = {"test.chord_angle"};
  const TestValues base = {{"chaotic", {{"chord_angle", 41.0}}}, {"a", {{"chord_angle", 41.0}}}};
  const TestValues now = {{"chaotic", {{"chord_angle", 45.0}}}, {"a", {{"chord_angle", 45.0}}}};
  // the ensembles ran: the ensemble's gate is the metric's, none here
  const std::vector<Gate> ran = gate_test_metrics("s", base, now, t, true);
  for (const Gate& g : ran)
    CHECK_FALSE((g.engine == "chaotic" && g.quantity == "test.chord_angle"));
  // --no-ensemble: shown, not gated, and saying why
  const std::vector<Gate> skipped = gate_test_metrics("s", base, now, t, false);
  const Gate& shown = gate_of(skipped, "chaotic", "test.chord_angle");
  CHECK_FALSE(shown.gated);
  CHECK(shown.note == kEnsembleElsewhere);
  // the other engine's move is still gated either way
  CHECK_FALSE(gate_of(ran, "a", "test.chord_angle").pass);
  CHECK_FALSE(gate_of(skipped, "a", "test.chord_angle").pass);
}

TEST_CASE("test metrics gate: a baseline tests.csv reads back what was written", "[regression]") {
  const test::TempDir dir("test-values");
  std::filesystem::create_directories(dir.path);
  const std::string path = (dir.path / "tests.csv").string();
  const TestValues v = {{"a", {{"bending_length", 0.0512345678901234}, {"folds", NAN}}},
                        {"b", {{"chord_angle", 41.5}}}};
  {
    CsvWriter w(path, {"engine", "metric", "value"});
    write_test_values(v, w);
    w.commit();
  }
  const TestValues back = read_test_values(path);
  REQUIRE(back.at("a").at("bending_length") == v.at("a").at("bending_length"));
  REQUIRE(std::isnan(back.at("a").at("folds")));
  REQUIRE(back.at("b").at("chord_angle") == 41.5);
  // a row given twice is refused with its line
  std::ofstream(path, std::ios::app) << "b,chord_angle,41.6\n";
  REQUIRE_THROWS_WITH(read_test_values(path), Contains("tests.csv:5") && Contains("second row"));
}
