/// @file bench_external.cpp
/// The cost of the external-engine protocol: the C++ example engine
/// (examples/external/cpp) stepped through the protocol, a frame of 10 steps per request,
/// against the same code called in-process, on the seed scene at 32 x 32 without contact.
/// Both report steps per second; the overhead is 1 - protocol / in-process.

#include <benchmark/benchmark.h>

#include "cloth/model/model.hpp"
#include "examples/external/cpp/mass_spring_engine.hpp"
#include "reference/external/external_engine.hpp"

namespace {

constexpr double kDt = 5e-5;        // s, well inside the 32 x 32 cloth's stable range
constexpr int kStepsPerFrame = 10;  // steps per request

cloth::Scene free_scene() {
  cloth::Scene s = cloth::seed_scene(32);
  s.spheres.clear();
  return s;
}

void BM_ExternalProtocol(benchmark::State& state) {
  clothbench::reference::ExternalOptions options;
  options.command = {CLOTHBENCH_EXAMPLE_ENGINE};
  clothbench::reference::ExternalEngine engine(options, free_scene(), kDt);
  for (auto _ : state) engine.advance(kDt, kStepsPerFrame);
  state.counters["steps_per_s"] = benchmark::Counter(
      double(kStepsPerFrame) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ExternalProtocol)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_ExternalInProcess(benchmark::State& state) {
  // the same model bytes the protocol sends, read by the same code
  const std::vector<char> model =
      clothbench::reference::external_model_payload(cloth::build_model(free_scene()), kDt);
  example::MassSpringEngine engine(model.data(), model.size());
  for (auto _ : state) {
    for (int s = 0; s < kStepsPerFrame; ++s) engine.step(kDt);
    benchmark::DoNotOptimize(engine.x.data());
  }
  state.counters["steps_per_s"] = benchmark::Counter(
      double(kStepsPerFrame) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ExternalInProcess)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
