/// @file bench_external.cpp
/// The cost of the external-engine protocol: the C++ example engine
/// (examples/external/cpp) stepped through the protocol, a frame of 10 steps per request,
/// against the same code called in-process, on the seed scene at 32 x 32 without contact.
/// BM_ExternalOverhead alternates the two frame by frame in one loop, so that a load that
/// comes and goes falls on both alike, and reports their ratio (protocol / in-process time,
/// the overhead is ratio - 1) and the time added per frame, and splits a protocol frame into
/// the harness's CPU, the engine's CPU and the time neither ran (idle_us: the hand-overs
/// between the processes, including their waits for a CPU on a loaded machine). Its argument
/// share_cpu is the engine key: 0 unpinned, 1 the benchmark's thread and the engine on one CPU
/// (the in-process frames then run on that CPU too), so one run reports both ratios.
/// BM_ExternalProtocol and
/// BM_ExternalInProcess time each alone (steps per second); the protocol's also counts the
/// sleeps (voluntary context switches) of the harness and of the engine per frame (at best one
/// each; an engine that is preempted before it waits for the next request sleeps less).
/// docs/external-engines.md has the command.

#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>

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

/// The C++ example engine, or the program CLOTHBENCH_BENCH_ENGINE names (another build of the
/// same example, say, to compare two versions of its protocol code in one run).
clothbench::reference::ExternalOptions example_engine() {
  clothbench::reference::ExternalOptions options;
  const char* other = std::getenv("CLOTHBENCH_BENCH_ENGINE");
  options.command = {other && *other ? other : CLOTHBENCH_EXAMPLE_ENGINE};
  return options;
}

/// The in-process copy: the same model bytes the protocol sends, read by the same code.
example::MassSpringEngine in_process_engine() {
  const std::vector<char> model =
      clothbench::reference::external_model_payload(cloth::build_model(free_scene()), kDt);
  return example::MassSpringEngine(model.data(), model.size());
}

/// Voluntary context switches (sleeps) of the process pid so far; 0 for the harness itself.
double sleeps(int pid) {
  if (pid == 0) {
    rusage u{};
    ::getrusage(RUSAGE_SELF, &u);
    return double(u.ru_nvcsw);
  }
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("voluntary_ctxt_switches:", 0) == 0) return std::stod(line.substr(24));
  return 0.0;
}

/// Steps per second of state's iterations, frames of kStepsPerFrame.
benchmark::Counter steps_per_s(const benchmark::State& state) {
  return benchmark::Counter(double(kStepsPerFrame) * double(state.iterations()),
                            benchmark::Counter::kIsRate);
}

void BM_ExternalProtocol(benchmark::State& state) {
  clothbench::reference::ExternalEngine engine(example_engine(), free_scene(), kDt);
  const double harness0 = sleeps(0), engine0 = sleeps(engine.pid());
  for (auto _ : state) engine.advance(kDt, kStepsPerFrame);
  const double frames = double(std::max<benchmark::IterationCount>(state.iterations(), 1));
  state.counters["harness_sleeps"] = (sleeps(0) - harness0) / frames;
  state.counters["engine_sleeps"] = (sleeps(engine.pid()) - engine0) / frames;
  state.counters["steps_per_s"] = steps_per_s(state);
}
BENCHMARK(BM_ExternalProtocol)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_ExternalInProcess(benchmark::State& state) {
  example::MassSpringEngine engine = in_process_engine();
  for (auto _ : state) {
    for (int s = 0; s < kStepsPerFrame; ++s) engine.step(kDt);
    benchmark::DoNotOptimize(engine.x.data());
  }
  state.counters["steps_per_s"] = steps_per_s(state);
}
BENCHMARK(BM_ExternalInProcess)->Unit(benchmark::kMicrosecond)->UseRealTime();

/// On-CPU time of the process pid so far (s), from /proc/PID/schedstat; 0 where the kernel
/// does not keep it.
double on_cpu(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/schedstat");
  double ns = 0.0;
  in >> ns;
  return 1e-9 * ns;
}

/// CPU time of the calling thread (s).
double thread_cpu() {
  timespec t{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

void BM_ExternalOverhead(benchmark::State& state) {
  using Clock = std::chrono::steady_clock;
  clothbench::reference::ExternalOptions options = example_engine();
  options.share_cpu = state.range(0) != 0;
  clothbench::reference::ExternalEngine external(options, free_scene(), kDt);
  if (options.share_cpu && external.cpu() < 0) state.SkipWithError("share_cpu: not pinned");
  example::MassSpringEngine local = in_process_engine();
  // s, summed over the frames: wall clock and the harness thread's CPU of each side
  double protocol = 0.0, in_process = 0.0, protocol_cpu = 0.0, in_process_cpu = 0.0;
  const double engine0 = on_cpu(external.pid());
  for (auto _ : state) {
    // one frame in-process, then the same frame through the protocol
    const auto t0 = Clock::now();
    const double c0 = thread_cpu();
    for (int s = 0; s < kStepsPerFrame; ++s) local.step(kDt);
    benchmark::DoNotOptimize(local.x.data());
    const double c1 = thread_cpu();
    const auto t1 = Clock::now();
    external.advance(kDt, kStepsPerFrame);
    const double c2 = thread_cpu();
    const auto t2 = Clock::now();
    in_process += std::chrono::duration<double>(t1 - t0).count();
    protocol += std::chrono::duration<double>(t2 - t1).count();
    in_process_cpu += c1 - c0;
    protocol_cpu += c2 - c1;
  }
  // the engine runs only while a protocol frame is under way
  const double engine_cpu = on_cpu(external.pid()) - engine0;
  const double frames = double(std::max<benchmark::IterationCount>(state.iterations(), 1));
  const double us = 1e6 / frames;
  state.counters["ratio"] = in_process > 0.0 ? protocol / in_process : 0.0;
  state.counters["added_us"] = us * (protocol - in_process);
  state.counters["cpu_ratio"] =
      in_process_cpu > 0.0 ? (protocol_cpu + engine_cpu) / in_process_cpu : 0.0;
  state.counters["in_process_cpu_us"] = us * in_process_cpu;
  state.counters["harness_cpu_us"] = us * protocol_cpu;
  state.counters["engine_cpu_us"] = us * engine_cpu;
  state.counters["idle_us"] = us * (protocol - protocol_cpu - engine_cpu);
}

/// The smallest and largest of the repetitions, for the ratio's spread.
double smallest(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end());
}
double largest(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}
BENCHMARK(BM_ExternalOverhead)
    ->ArgName("share_cpu")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime()
    ->ComputeStatistics("min", smallest)
    ->ComputeStatistics("max", largest);

}  // namespace

BENCHMARK_MAIN();
