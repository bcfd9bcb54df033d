/// @file bench_self_contact.cpp
/// Self-contact benchmarks of the custom engine (Google Benchmark; not part of ctest).
///   BM_self_contact_pile/<off|on>: one custom-rk4 step (the scenario's h = 5e-4 s) of
///     scenarios/cloth_pile.toml in its piled state: the scene is run once to its end (2.5 s)
///     with self-contact on and its positions and velocities kept; the timed steps follow one
///     another from that state (MassSpringCloth::set_state, once) in an engine with
///     self_collision off or on and without the gripper's handle (set_state puts held
///     particles back where they started, which would make the gripped corner jump 0.66 m;
///     freed, the corner drops the 0.09 m onto the pile in the first steps and the pile
///     settles), with self_contact_tests per step (narrow-phase pair tests, the candidate
///     filter's included).
///     Run: build/release/tests/benchmark/clothbench-bench --benchmark_filter=BM_self_contact_pile

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "cloth/integrators/mass_spring_cloth.hpp"
#include "harness/engines/engine_factory.hpp"
#include "harness/scenario/scenario_loader.hpp"

namespace {

using namespace cloth;
using namespace clothbench;

/// The pile scenario and its custom-rk4 engine's spec with self-collision on or off.
struct PileScene {
  Scenario scenario;
  EngineSpec spec;
};

PileScene pile_scene(bool self_collision) {
  PileScene p{load_scenario(std::string(CLOTHBENCH_SOURCE_DIR) + "/scenarios/cloth_pile.toml"), {}};
  for (const EngineSpec& e : p.scenario.engines)
    if (e.name == "custom-rk4") p.spec = e;
  p.spec.self_collision = self_collision;
  return p;
}

std::unique_ptr<MassSpringCloth> custom_engine(const PileScene& p) {
  std::unique_ptr<Simulator> sim = make_engine(p.spec, p.scenario.scene);
  std::unique_ptr<MassSpringCloth> cloth(dynamic_cast<MassSpringCloth*>(sim.get()));
  if (cloth) sim.release();
  return cloth;
}

/// Runs sim over the whole scene.
void run_to_end(const PileScene& p, MassSpringCloth& sim) {
  const long steps = std::lround(p.scenario.duration / p.spec.dt);
  for (long i = 0; i < steps; ++i) sim.step(p.spec.dt);
}

/// The state at the end of the pile scene with self-contact on, computed once.
struct PiledState {
  Matrix3X x, v;
};

const PiledState& piled_state() {
  static const PiledState state = [] {
    const PileScene p = pile_scene(true);
    std::unique_ptr<MassSpringCloth> sim = custom_engine(p);
    run_to_end(p, *sim);
    return PiledState{sim->positions(), sim->velocities()};
  }();
  return state;
}

void BM_self_contact_pile(benchmark::State& state, bool on) {
  const PiledState& piled = piled_state();
  // the scene without its handle
  PileScene p = pile_scene(on);
  p.scenario.scene.handles.clear();
  std::unique_ptr<MassSpringCloth> sim = custom_engine(p);
  if (!sim) {
    state.SkipWithError("custom-rk4 is not the custom engine");
    return;
  }
  // steps follow each other from the piled state, so the pass's candidate list is rebuilt as
  // often as the cloth's own motion makes it
  sim->set_state(piled.x, piled.v);
  const std::int64_t tests0 = sim->counters().self_contact_tests;
  for (auto _ : state) {
    sim->step(p.spec.dt);
    benchmark::DoNotOptimize(sim->positions().data());
  }
  state.counters["self_contact_tests"] =
      benchmark::Counter(static_cast<double>(sim->counters().self_contact_tests - tests0),
                         benchmark::Counter::kAvgIterations);
}
BENCHMARK_CAPTURE(BM_self_contact_pile, off, false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_self_contact_pile, on, true)->Unit(benchmark::kMicrosecond);

}  // namespace
