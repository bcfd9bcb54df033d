// The schema of the scenario file (clothbench schema --scenario) against the loader: a row for
// every key the loader accepts and none it does not, and the ranges the rows state are the ones
// the loader enforces. The output files' schema against the writers is tests/schema/.

#include <catch2/catch.hpp>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "format/number_format.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/scenario/engine_kind.hpp"
#include "harness/scenario/scenario_error.hpp"
#include "harness/scenario/scenario_format.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_schema.hpp"
#include "harness/scenario/toml_reader.hpp"

using namespace clothbench;
using Catch::Matchers::Contains;

namespace {

/// (table, kind, key) of a row or of a key the loader accepts.
using KeyId = std::tuple<std::string, std::string, std::string>;

/// Every key the loader's key lists accept, by the table it is read in.
std::set<KeyId> accepted_keys() {
  std::set<KeyId> keys;
  const auto add = [&](const std::string& table, const Keys& list, const std::string& kind = "") {
    for (std::string_view k : list) keys.emplace(table, kind, std::string(k));
  };
  add("", kTopKeys);
  add("cloth", kClothKeys);
  add("cloth.stiffness", kStiffnessKeys);
  add("cloth.generate", kGenerateKeys);
  add("constraint", kConstraintKeys);
  add("handle", kHandleKeys);
  add("sphere", kSphereKeys);
  for (const auto& [table, own] : {std::pair<const char*, const Keys*>{"plane", &kPlaneKeys},
                                   {"box", &kBoxKeys},
                                   {"capsule", &kCapsuleKeys},
                                   {"cylinder", &kCylinderKeys}}) {
    add(table, *own);
    add(table, kColliderKeys);
  }
  add("test", kTestKeys);
  add("engine", kEngineCommonKeys);
  for (const EngineKindInfo& info : engine_kind_table()) add("engine", info.keys, info.name);
  return keys;
}

/// A scenario with one table of every kind and one engine of every kind, each key reachable.
const char* const kEverything = R"(
name = "everything"
duration = 0.02
frame_interval = 0.01
[cloth]
particles = [5, 5]
size = [1.0, 1.0]
stiffness = { structural = 100.0, shear = 100.0, bend = 10.0 }
[[constraint]]
select = "disk"
center = [-0.5, -0.5]
radius = 0.1
[[handle]]
select = "disk"
center = [0.5, 0.5]
radius = 0.1
path = [[0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.1, 0.0]]
[[sphere]]
center = [0.0, -1.0, 0.0]
[[plane]]
point = [0.0, -2.0, 0.0]
[[box]]
center = [3.0, 0.0, 0.0]
[[capsule]]
radius = 0.1
[[cylinder]]
center = [0.0, -3.0, 0.0]
[[constraint]]
select = "edge:u0"
[test]
kind = "cantilever"
edge = -0.5
[[engine]]
name = "custom"
kind = "custom"
dt = 1e-3
[[engine]]
name = "bullet-deformable"
kind = "bullet-deformable"
dt = 1e-3
[[engine]]
name = "bullet-softbody"
kind = "bullet-softbody"
dt = 1e-3
[[engine]]
name = "mujoco"
kind = "mujoco"
dt = 1e-3
[[engine]]
name = "external"
kind = "external"
command = ["my-engine"]
dt = 1e-3
)";

/// The same with a generated mesh for its cloth, for the keys of [cloth.generate].
const char* const kEverythingMesh = R"(
name = "everything-mesh"
duration = 0.02
frame_interval = 0.01
[cloth]
areal_density = 0.2
stiffness = { structural = 100.0, bend = 10.0 }
[cloth.generate]
shape = "disk"
radius = 0.1
edge_length = 0.05
[[engine]]
name = "custom"
kind = "custom"
dt = 1e-3
)";

/// The --set key of a row in kEverything: "sphere.0.radius", "engine.custom.dt".
std::string override_key(const ScenarioKey& k) {
  if (k.table == "engine") return "engine." + (k.kind.empty() ? "custom" : k.kind) + "." + k.key;
  for (const char* array :
       {"constraint", "handle", "sphere", "plane", "box", "capsule", "cylinder"})
    if (k.table == array) return k.table + ".0." + k.key;
  return k.path();
}

/// A value the row's range refuses, as TOML ("" when it refuses no number).
std::string outside(const ScenarioKey& k) {
  if (k.integer)
    return std::to_string(k.max < std::numeric_limits<int>::max() ? k.max + 1 : k.min - 1);
  for (double v : {-1.0, 0.0, 1.5})
    if (!k.bound->ok(v)) return toml_double(v);
  return "";
}

}  // namespace

TEST_CASE("schema: a row for every key the loader accepts, and none it does not", "[schema]") {
  std::set<KeyId> rows;
  for (const ScenarioKey& k : scenario_keys()) {
    INFO(k.path() << " " << k.kind);
    CHECK(rows.emplace(k.table, k.kind, k.key).second);  // no row twice
    CHECK_FALSE(k.type.empty());
    CHECK_FALSE(k.default_value.empty());
    CHECK_FALSE(k.meaning.empty());
  }
  const std::set<KeyId> accepted = accepted_keys();
  for (const KeyId& k : accepted) {
    INFO("accepted by the loader, no schema row: " << std::get<0>(k) << "." << std::get<2>(k) << " "
                                                   << std::get<1>(k));
    CHECK(rows.count(k) == 1);
  }
  for (const KeyId& k : rows) {
    INFO("schema row, not accepted by the loader: " << std::get<0>(k) << "." << std::get<2>(k)
                                                    << " " << std::get<1>(k));
    CHECK(accepted.count(k) == 1);
  }
}

TEST_CASE("schema: the ranges in the table are the ones the loader enforces", "[schema]") {
  // every engine's keys are read; only the custom engine must model the scene
  const std::vector<std::string> only = {"custom"};
  REQUIRE_NOTHROW(parse_scenario(kEverything, "everything.toml", {}, only));
  REQUIRE_NOTHROW(parse_scenario(kEverythingMesh, "everything-mesh.toml", {}, only));
  int checked = 0;
  for (const ScenarioKey& k : scenario_keys()) {
    std::string value;
    if (k.integer || k.bound)
      value = outside(k);
    else if (k.range.rfind("one of ", 0) == 0)
      value = "\"no-such-value\"";
    if (value.empty()) continue;
    const std::string set = override_key(k) + "=" + value;
    INFO("--set " << set << " (schema range: " << k.range << ")");
    // refused, naming the key, with the range the table states
    const char* text = k.table == "cloth.generate" ? kEverythingMesh : kEverything;
    // a shape's own size keys are read for that shape only
    std::vector<std::string> sets = {set};
    if (k.path() == "cloth.generate.inner_radius")
      sets.insert(sets.begin(), "cloth.generate.shape=\"annulus\"");
    if (k.path() == "cloth.generate.length")
      sets.insert(sets.begin(), "cloth.generate.shape=\"tube\"");
    CHECK_THROWS_WITH(parse_scenario(text, "everything.toml", sets, only),
                      Contains("--set " + override_key(k)) && Contains(k.range));
    ++checked;
  }
  CHECK(checked > 40);
}

TEST_CASE("schema: the enumerated values are listed from their enums' own tables", "[schema]") {
  CHECK(integrator_names().size() == cloth::all_integrators().size());
  CHECK(kNewtonMethods.size() == cloth::all_newton_methods().size());
  CHECK(kLinearSolvers.size() == cloth::all_linear_solvers().size());
  CHECK(kCgForcings.size() == cloth::all_cg_forcings().size());
  for (std::string_view name : kNewtonMethods) CHECK(cloth::parse_newton_method(name));
  for (std::string_view name : kLinearSolvers) CHECK(cloth::parse_linear_solver(name));
  for (std::string_view name : kCgForcings) CHECK(cloth::parse_cg_forcing(name));
  for (std::string_view name : kPlanes) CHECK(parse_plane(name));
  for (std::string_view name : kSoftbodyStiffness)
    CHECK(reference::parse_softbody_stiffness(std::string(name)));
}

TEST_CASE("schema: both tables are deterministic Markdown", "[schema]") {
  CHECK(scenario_schema_markdown() == scenario_schema_markdown());
  CHECK(output_schema_markdown() == output_schema_markdown());
  CHECK_THAT(scenario_schema_markdown(),
             Catch::StartsWith("| key | type | unit | default | range | meaning |\n"));
  // every row of both tables has as many cells as its heading ('|' in a cell is escaped)
  const auto bars = [](const std::string& line) {
    int n = 0;
    for (size_t k = 0; k < line.size(); ++k) n += line[k] == '|' && (k == 0 || line[k - 1] != '\\');
    return n;
  };
  for (const std::string& table : {scenario_schema_markdown(), output_schema_markdown()}) {
    std::istringstream lines(table);
    int heading = 0;
    for (std::string line; std::getline(lines, line);) {
      if (line.empty() || line[0] != '|') {
        heading = 0;
        continue;
      }
      if (heading == 0) heading = bars(line);
      INFO(line);
      CHECK(bars(line) == heading);
    }
  }
  // every output column has a unit and a meaning, and no file is listed twice
  std::set<std::string> names;
  for (const OutputFile& f : output_files()) {
    CHECK(names.insert(f.name).second);
    for (const OutputColumn& c : f.columns) {
      INFO(f.name << " " << c.name);
      CHECK(*c.unit);
      CHECK(*c.meaning);
    }
  }
}

TEST_CASE("numbers for a reader keep the significant digits asked for", "[format]") {
  CHECK(cloth::significant(12345.678, 4) == "1.235e+04");
  CHECK(cloth::significant(0.0123456, 3) == "0.0123");
  CHECK(cloth::significant(2.0, 6) == "2");
  CHECK(cloth::significant(-0.5, 4) == "-0.5");
  CHECK(cloth::significant(std::numeric_limits<double>::quiet_NaN(), 4) == "nan");
  CHECK(cloth::significant(-std::numeric_limits<double>::infinity(), 4) == "-inf");
}
