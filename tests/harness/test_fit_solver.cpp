// The one-parameter solver of clothbench fit on analytic monotone functions: it brackets and
// converges from far away, in either direction, says when a target is out of reach, and
// treats a run without a metric (a blow-up) as the end of the range. And the targets a
// fabric preset gives each scenario (--fabric), and the bending lengths a cantilever cannot
// show at any stiffness.

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "harness/scenario/fabric_preset.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/sweeps/fit_reach.hpp"
#include "harness/sweeps/fit_solver.hpp"
#include "harness/sweeps/fit_sweep.hpp"

using namespace clothbench;

namespace {

/// Options for target with the solver's default tolerance (3 %), from start.
FitSolverOptions aim(double target, double start) {
  FitSolverOptions o;
  o.target = target;
  o.start = start;
  return o;
}

}  // namespace

TEST_CASE("the fit solver converges on monotone functions from far away", "[fit]") {
  // a bending length grows as the cube root of the stiffness; a sag falls as 1 / stiffness
  const double k0 = GENERATE(0.02, 3.0, 4000.0);
  const double start = GENERATE(1.0, 1000.0);
  const auto cube_root = [](double k) { return 0.01 * std::cbrt(k); };
  const auto inverse = [](double k) { return 2.0 / k; };
  for (const auto& f :
       {std::function<double(double)>(cube_root), std::function<double(double)>(inverse)}) {
    FitSolverOptions o = aim(f(k0), start);
    o.lo = 1e-6;
    o.hi = 1e6;
    const FitResult r = solve_monotone(f, o);
    CAPTURE(k0, start, r.note, r.samples.size());
    REQUIRE(r.status == FitStatus::converged);
    REQUIRE(std::abs(r.metric - o.target) <= o.tolerance * o.target);
    REQUIRE(r.metric == f(r.parameter));
    // bracketing doubles its log step, so even 1e5 away takes few runs
    REQUIRE(r.samples.size() <= 12);
  }
}

TEST_CASE("the fit solver measures the sensitivity on its way", "[fit]") {
  // m = p^2, d m / d p = 2 p: the secant between the best run and its nearest neighbour (in log
  // p) lies between the derivatives at the two (the mean value theorem, f' increasing)
  const auto square = [](double p) { return p * p; };
  FitSolverOptions o = aim(9.0, 1.0);
  o.tolerance = 1e-4;
  const FitResult r = solve_monotone(square, o);
  REQUIRE(r.status == FitStatus::converged);
  REQUIRE(r.parameter == Approx(3.0).epsilon(1e-4));
  double other = 0.0;
  for (const FitSample& s : r.samples)
    if (s.parameter != r.parameter &&
        (other == 0.0 ||
         std::abs(std::log(s.parameter / r.parameter)) < std::abs(std::log(other / r.parameter))))
      other = s.parameter;
  const double lo = 2 * std::min(other, r.parameter), hi = 2 * std::max(other, r.parameter);
  CAPTURE(other, r.sensitivity);
  REQUIRE(r.sensitivity >= lo);
  REQUIRE(r.sensitivity <= hi);
}

TEST_CASE("the fit solver says when a target is out of reach and gives the best", "[fit]") {
  SECTION("beyond the range") {
    FitSolverOptions o = aim(100.0, 1.0);
    o.hi = 10.0;
    const FitResult r = solve_monotone([](double p) { return p; }, o);
    REQUIRE(r.status == FitStatus::unreachable);
    REQUIRE(r.parameter == Approx(10.0));
    REQUIRE(r.metric == Approx(10.0));
  }
  SECTION("on a plateau (a stiffness the engine cannot give)") {
    FitSolverOptions o = aim(2.0, 1.0);
    const FitResult r = solve_monotone([](double p) { return 1.0 - std::exp(-p); }, o);
    REQUIRE(r.status == FitStatus::unreachable);
    REQUIRE(r.metric == Approx(1.0).epsilon(1e-3));
    REQUIRE(r.samples.size() < 12);
  }
  SECTION("past a blow-up") {
    // no metric above p = 50: the range ends there
    const auto blows = [](double p) { return p < 50.0 ? std::cbrt(p) : NAN; };
    FitSolverOptions o = aim(std::cbrt(40.0), 1.0);
    const FitResult reached = solve_monotone(blows, o);
    REQUIRE(reached.status == FitStatus::converged);
    o.target = std::cbrt(100.0);
    o.max_runs = 30;
    const FitResult beyond = solve_monotone(blows, o);
    REQUIRE(beyond.status == FitStatus::unreachable);
    REQUIRE(beyond.parameter < 50.0);
    REQUIRE(beyond.parameter > 45.0);
  }
  SECTION("no run gives a metric") {
    const FitResult r = solve_monotone([](double) { return NAN; }, aim(1.0, 1.0));
    REQUIRE(r.status == FitStatus::failed);
    REQUIRE(std::isnan(r.metric));
  }
}

TEST_CASE("the fit solver stops at its run budget", "[fit]") {
  FitSolverOptions o = aim(1e4, 1.0);
  o.max_runs = 3;
  o.hi = 1e9;
  const FitResult r = solve_monotone([](double p) { return p; }, o);
  REQUIRE(r.status == FitStatus::budget);
  REQUIRE(r.samples.size() == 3);
  // the best of the three: the last, furthest up
  REQUIRE(r.parameter == r.samples.back().parameter);
}

TEST_CASE("a fabric's targets are the metrics its measurements give", "[fit]") {
  Fabric f;
  f.name = "test";
  f.areal_density = 0.25;
  f.bending_warp = 2e-5;
  f.bending_weft = 1e-5;
  f.tensile_warp = 3000.0;
  f.tensile_weft = 1500.0;
  f.drape_coefficient = 0.55;
  const std::string dir = CLOTHBENCH_SOURCE_DIR "/scenarios/";
  // the cantilever: its bending length is the one whose heavy strip has the warp's rigidity,
  // B = rho_A g c^3 (the cantilever's flexural_rigidity)
  const auto cantilever = fabric_targets(f, load_scenario(dir + "fabric/cantilever.toml"));
  REQUIRE(cantilever.size() == 1);
  REQUIRE(cantilever[0].metric == "bending_length");
  REQUIRE(f.areal_density * kStandardGravity * std::pow(cantilever[0].value, 3) ==
          Approx(f.bending_warp).epsilon(1e-12));
  // the strips: the stiffness along the direction pulled
  const auto weft = fabric_targets(f, load_scenario(dir + "fabric/strip-tensile-weft.toml"));
  REQUIRE(weft.size() == 1);
  REQUIRE(weft[0].metric == "tensile_stiffness");
  REQUIRE(weft[0].value == 1500.0);
  // the Cusick scene: the drape coefficient as measured
  const auto drape = fabric_targets(f, load_scenario(dir + "cusick_drape.toml"));
  REQUIRE(drape.size() == 1);
  REQUIRE(drape[0].metric == "drape_coefficient");
  REQUIRE(drape[0].value == 0.55);
  // a fabric without a drape measurement gives the Cusick scene no target
  f.drape_coefficient.reset();
  REQUIRE(fabric_targets(f, load_scenario(dir + "cusick_drape.toml")).empty());
}

TEST_CASE("a bending length a cantilever cannot show is unreachable before any run", "[fit]") {
  const std::string dir = CLOTHBENCH_SOURCE_DIR "/scenarios/";
  // the file's strip runs from x = -0.1 to 0.1 m over an edge at 0: 0.1 m overhang
  const Scenario s = load_scenario(dir + "fabric/cantilever.toml");
  REQUIRE(cantilever_overhang(s) == Approx(0.1).epsilon(1e-12));
  // the elastica gives c only while l / c <= 6 (chord 83.9 degrees): c >= 0.1 / 6 = 0.01667 m,
  // a target counting as reached within its tolerance
  const auto short_c = unmeasurable_target("bending_length", 0.016, 0.0003, s);
  REQUIRE(short_c);
  REQUIRE(short_c->find("83.9 degrees") != std::string::npos);
  REQUIRE(short_c->find("at most 6 c = 0.096 m") != std::string::npos);
  REQUIRE_FALSE(unmeasurable_target("bending_length", 0.016, 0.001, s));
  REQUIRE_FALSE(unmeasurable_target("bending_length", 0.03, 0.0009, s));
  // flexural rigidity G = rho_A g c^3: the same bound, 0.2 x 9.8 x (0.1 / 6)^3 = 9.07e-6 N m
  const double g_min = 0.2 * 9.8 * std::pow(0.1 / 6.0, 3);
  REQUIRE(unmeasurable_target("flexural_rigidity", 0.9 * g_min, 0.01 * g_min, s));
  REQUIRE_FALSE(unmeasurable_target("flexural_rigidity", 1.1 * g_min, 0.01 * g_min, s));
  // other metrics and other tests: the harness cannot tell
  REQUIRE_FALSE(unmeasurable_target("bending_length_peirce", 0.001, 0.0, s));
  const Scenario strip = load_scenario(dir + "fabric/strip-tensile-warp.toml");
  REQUIRE(std::isnan(cantilever_overhang(strip)));
  REQUIRE_FALSE(unmeasurable_target("bending_length", 0.001, 0.0, strip));
}
