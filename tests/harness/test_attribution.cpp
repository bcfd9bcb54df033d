#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "harness/io/user_error.hpp"
#include "harness/run/attribution.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "temp_dir.hpp"

using namespace clothbench;

namespace {

/// Round-off allowed in the triangle inequality between three RMS distances (m).
constexpr double kTriangleSlack = 1e-12;
/// imex-euler is Bullet's explicit scheme: without contact the model part is round-off and
/// CG tolerance (README, imex-euler: 2e-10 m on the flag over 2 s).
constexpr double kNoModelDifference = 1e-6;  // m

/// The shipped flag over 0.5 s with every Bullet engine and the reference, explained.
RunResult explained_flag() {
  Scenario sc =
      load_scenario(std::string(CLOTHBENCH_SOURCE_DIR) + "/scenarios/flag.toml", {"duration=0.5"});
  std::vector<std::string> names = {"custom-rk4", "bullet-deformable-explicit",
                                    "bullet-deformable-implicit", "bullet-softbody-matched"};
  add_matched_engines(sc, names);
  RunOptions o;
  o.engines = names;
  o.progress = false;
  return run_scenario(sc, o);
}

}  // namespace

TEST_CASE("run --explain adds the matched scheme of each bullet-deformable mode", "[attribution]") {
  Scenario sc = load_scenario(std::string(CLOTHBENCH_SOURCE_DIR) + "/scenarios/flag.toml");
  std::vector<std::string> all;
  add_matched_engines(sc, all);
  CHECK(all.empty());  // no filter: none to extend
  const EngineSpec* ex = nullptr;
  const EngineSpec* im = nullptr;
  for (const EngineSpec& e : sc.engines) {
    if (e.name == "custom-as-bullet-deformable-explicit") ex = &e;
    if (e.name == "custom-as-bullet-deformable-implicit") im = &e;
    CHECK(e.name != "custom-as-bullet-softbody-matched");  // position-based: no match
  }
  REQUIRE(ex);
  REQUIRE(im);
  CHECK(ex->solver.integrator == cloth::Integrator::imex_euler);
  CHECK(ex->dt == 1e-3);
  CHECK(im->solver.integrator == cloth::Integrator::implicit_euler);
  CHECK(im->solver.newton_iterations == 1);
  CHECK_FALSE(im->solver.clamp_compressed);
  // --explain on a scenario.toml that --explain wrote runs the engines it holds
  const size_t count = sc.engines.size();
  add_matched_engines(sc, all);
  CHECK(sc.engines.size() == count);
  // but a name taken by another engine is refused
  for (EngineSpec& e : sc.engines)
    if (e.name == "custom-as-bullet-deformable-explicit") e.dt = 2e-3;
  CHECK_THROWS_AS(add_matched_engines(sc, all), UserError);
}

TEST_CASE("attribution.csv splits each Bullet engine's distance, softbody unsplit",
          "[attribution]") {
  const RunResult r = explained_flag();
  const std::vector<AttributionRow> rows = attribution(r);
  REQUIRE(rows.size() == 6);  // three Bullet engines, final and max each
  for (const AttributionRow& row : rows) {
    INFO(row.engine << " " << row.at << ": total " << row.total_rms << ", scheme " << row.scheme_rms
                    << ", model " << row.model_rms);
    CHECK(row.reference == "custom-rk4");
    CHECK(std::abs(row.t - 0.5) < 1e-12);
    CHECK(row.total_rms > 0.0);
    if (row.engine == "bullet-softbody-matched") {
      CHECK(row.matched.empty());
      CHECK(std::isnan(row.scheme_rms));
      CHECK(std::isnan(row.model_rms));
      CHECK(row.note.find("no custom time scheme") != std::string::npos);
      continue;
    }
    CHECK(row.matched == "custom-as-" + row.engine);
    CHECK(row.note.empty());
    // the three distances are norms of differences of three states: a triangle
    CHECK(row.total_rms <= row.scheme_rms + row.model_rms + kTriangleSlack);
    CHECK(row.scheme_rms <= row.total_rms + row.model_rms + kTriangleSlack);
    CHECK(row.model_rms <= row.total_rms + row.scheme_rms + kTriangleSlack);
    if (row.engine == "bullet-deformable-explicit") CHECK(row.model_rms < kNoModelDifference);
  }
  // max is the largest over the frames, so never below final
  for (size_t k = 0; k + 1 < rows.size(); k += 2) {
    REQUIRE(rows[k].at == "final");
    REQUIRE(rows[k + 1].at == "max");
    CHECK(rows[k + 1].total_rms >= rows[k].total_rms);
  }
}

TEST_CASE("attribution.csv has its columns and an empty split for softbody", "[attribution]") {
  const RunResult r = explained_flag();
  const clothbench::test::TempDir dir("attribution");
  std::filesystem::create_directories(dir.path);
  write_attribution(r, dir.str());
  std::ifstream in(dir.path / "attribution.csv");
  std::string header, line;
  std::getline(in, header);
  CHECK(header == "engine,reference,matched,at,t,total_rms,scheme_rms,model_rms,note");
  int rows = 0, unsplit = 0;
  while (std::getline(in, line)) {
    ++rows;
    if (line.rfind("bullet-softbody-matched,custom-rk4,,", 0) == 0) {
      ++unsplit;
      std::vector<std::string> f;
      std::stringstream fields(line);
      for (std::string x; f.size() < 8 && std::getline(fields, x, ',');) f.push_back(x);
      REQUIRE(f.size() == 8);
      CHECK_FALSE(f[5].empty());  // total_rms is there
      CHECK(f[6].empty());        // scheme_rms and model_rms are not
      CHECK(f[7].empty());
    }
  }
  CHECK(rows == 6);
  CHECK(unsplit == 2);
}
