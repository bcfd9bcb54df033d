/// @file bench_mujoco.cpp
/// The mujoco engine's memory at 16 x 16, 32 x 32 and 48 x 48 (the table in docs/engines.md)
/// and its step time: the seed scene's cloth, with its sphere (contacts, so the constraint
/// arrays are allocated) or without any collider.

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>

#include "cloth/model/scene.hpp"
#include "reference/mujoco/mujoco_cloth.hpp"

namespace {

/// The resident set of this process (bytes), from /proc/self/status.
double resident_bytes() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0.0;
  char line[256];
  double kb = 0.0;
  while (std::fgets(line, sizeof line, f))
    if (std::strncmp(line, "VmRSS:", 6) == 0) kb = std::atof(line + 6);
  std::fclose(f);
  return kb * 1024.0;
}

/// Builds the seed scene at n = range(0) by n (with its sphere when range(1) is 1), with the
/// integrator numbered range(2) (0 euler, 1 rk4, 2 implicit), steps it 0.2 s at dt = 1e-3 s
/// (implicit: 2 steps) and reports the sizes.
void BM_MujocoMemory(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  cloth::Scene scene = cloth::seed_scene(n);
  if (state.range(1) == 0) scene.spheres.clear();
  clothbench::reference::MujocoOptions options;
  options.integrator = static_cast<clothbench::reference::MujocoIntegrator>(state.range(2));
  if (const auto refusal = clothbench::reference::mujoco_refusal(options, scene)) {
    state.SkipWithError(refusal->why.c_str());
    return;
  }
  for (auto _ : state) {
    const double before = resident_bytes();
    auto engine = clothbench::reference::make_mujoco_cloth(options, 1e-3, scene);
    // implicit: its dense factorisation takes seconds a step at 32 x 32 and fills the same
    // stack every step, so two steps measure it
    const int steps =
        options.integrator == clothbench::reference::MujocoIntegrator::implicit ? 2 : 200;
    for (int i = 0; i < steps; ++i) engine->step(1e-3);
    const auto m = clothbench::reference::mujoco_measure(*engine);
    state.counters["model_MB"] = m.model_bytes / 1e6;
    state.counters["buffer_MB"] = m.buffer_bytes / 1e6;
    state.counters["stack_MB"] = m.stack_bytes / 1e6;
    state.counters["stack_used_MB"] = m.stack_used / 1e6;
    state.counters["estimate_MB"] = m.size.total_bytes() / 1e6;
    state.counters["rss_MB"] = (resident_bytes() - before) / 1e6;
    state.counters["contacts"] = engine->contacts();
  }
}
BENCHMARK(BM_MujocoMemory)
    ->ArgsProduct({{16, 32, 48}, {0, 1}, {0, 2}})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace
