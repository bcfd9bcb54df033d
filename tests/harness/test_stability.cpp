#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "cloth/linear_stability.hpp"
#include "harness/scenario_loader.hpp"
#include "harness/stability_sweep.hpp"

using namespace clothbench;

namespace {

// a small cloth on its four corners, all spring kinds equal (damping proportional to
// stiffness: the linear prediction is exact), no contact
const char* kScene = R"(
name = "small_prop"
duration = 1.0
frame_interval = 0.01
[cloth]
particles = [8, 8]
size = [0.7, 0.7]
center = [0.0, 1.0, 0.0]
particle_mass = 0.01
stiffness = { structural = 100.0, shear = 100.0, bend = 100.0 }
damping = 0.3
[[constraint]]
select = "corners"
hold = "xyz"
[[engine]]
name = "custom"
integrator = "rk4"
dt = 1e-4
)";

}  // namespace

TEST_CASE("measured stability limits bracket the predicted ones", "[stability][sweep]") {
  const cloth::Integrator integrator = GENERATE(
      cloth::Integrator::explicit_euler, cloth::Integrator::symplectic_euler,
      cloth::Integrator::picard_implicit, cloth::Integrator::midpoint, cloth::Integrator::rk4);
  const Scenario sc = parse_scenario(kScene, "small.toml");
  const cloth::LinearSpectrum s = cloth::linear_spectrum(cloth::build_model(sc.scene));
  REQUIRE(s.exact);
  const double predicted = cloth::predicted_stable_dt(integrator, s);
  EngineSpec e = sc.engines[0];
  e.solver.integrator = integrator;
  INFO(cloth::integrator_name(integrator) << ": predicted " << predicted << " s");
  // below the limit every mode decays; well above it the fastest mode grows to a blow-up
  // within the second (finite duration: a step just above the limit grows too slowly)
  e.dt = 0.95 * predicted;
  CHECK(stable_run(sc, e, nullptr));
  e.dt = 1.3 * predicted;
  std::string cause;
  CHECK_FALSE(stable_run(sc, e, &cause));
}

TEST_CASE("the stability search writes one reproducible row per integrator", "[stability][sweep]") {
  const Scenario sc = parse_scenario(kScene, "small.toml", {"duration=0.3"});
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "clothbench-stab";
  std::filesystem::remove_all(dir);
  StabilityOptions o;
  o.out_dir = dir.string();
  o.integrators = {"explicit-euler", "midpoint"};
  o.progress = false;
  o.jobs = 2;
  const std::vector<StabilityRow> rows = run_stability(sc, o);
  REQUIRE(rows.size() == 2);
  for (const StabilityRow& r : rows) {
    INFO(r.integrator << " stable " << r.stable_dt << " unstable " << r.first_unstable_dt);
    CHECK(r.first_unstable_dt > r.stable_dt);
    CHECK(r.first_unstable_dt / r.stable_dt - 1.0 <= o.rel_tol);
    CHECK(r.rerun.find("engine.custom.dt=") != std::string::npos);
    CHECK(r.cause.find("limiting mode omega") != std::string::npos);
    // the row reruns: stable at stable_dt, unstable at first_unstable_dt
    EngineSpec e = with_integrator_and_dt(sc.engines[0], r.integrator, r.stable_dt);
    CHECK(stable_run(sc, e, nullptr));
    e.dt = r.first_unstable_dt;
    CHECK_FALSE(stable_run(sc, e, nullptr));
  }
  // resume keeps the rows and runs nothing new
  o.resume = true;
  const std::vector<StabilityRow> again = run_stability(sc, o);
  for (size_t i = 0; i < rows.size(); ++i) CHECK(again[i].stable_dt == rows[i].stable_dt);
  std::ifstream in(dir / "stability.csv");
  std::string header;
  std::getline(in, header);
  CHECK(header ==
        "engine,integrator,stable_dt,first_unstable_dt,predicted_dt,ratio_measured_to_predicted,"
        "cause,runs,rerun");
}
