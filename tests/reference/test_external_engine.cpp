/// @file test_external_engine.cpp
/// The external-engine protocol (reference/external): the example engines (Python + numpy, and
/// C++) against the custom engine's symplectic Euler on the seed scene without contact, the
/// state requests, and every way an engine can misbehave (tests/data/external/
/// misbehaving_engine.py), which must fail the engine's run with its reason and never hang;
/// share_cpu (the engine and the run's thread on one CPU, cpu_pin.hpp).

#include <sched.h>
#include <signal.h>
#include <sys/wait.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <thread>

#include "cloth/integrators/mass_spring_cloth.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_writer.hpp"
#include "harness/stability/stability_sweep.hpp"
#include "reference/external/external_engine.hpp"
#include "temp_dir.hpp"
#include "tolerances.hpp"

using namespace clothbench;
using reference::ExternalEngine;
using reference::ExternalOptions;

namespace {

const std::string kSource = CLOTHBENCH_SOURCE_DIR;
const std::string kPythonEngine = kSource + "/examples/external/python/cloth_engine.py";
const std::string kMisbehaving = kSource + "/tests/data/external/misbehaving_engine.py";

/// The seed scene without its sphere: a 25 x 25 cloth pinned at its corners, no contact.
cloth::Scene free_seed_scene() {
  cloth::Scene s = cloth::seed_scene(25);
  s.spheres.clear();
  return s;
}

ExternalOptions misbehaving(const std::string& mode, double timeout = 10.0) {
  return {{"/usr/bin/python3", kMisbehaving, mode}, timeout};
}

/// True when no process pid exists any more (reaped, not a zombie).
bool gone(int pid) {
  return ::kill(pid, 0) != 0 && errno == ESRCH;
}

/// Runs advance on a fresh engine of options and returns what it threw ("" if nothing).
std::string failure_of(const ExternalOptions& options) {
  try {
    ExternalEngine e(options, free_seed_scene(), 1e-3);
    e.advance(1e-3, 10);
    return "";
  } catch (const cloth::EngineFailure& f) {
    return f.what();
  }
}

}  // namespace

TEST_CASE("The example external engines match custom symplectic Euler to round-off", "[external]") {
  const std::string command = GENERATE(std::string("python"), std::string("cpp"));
  ExternalOptions options;
  options.command = command == "python"
                        ? std::vector<std::string>{"/usr/bin/python3", kPythonEngine}
                        : std::vector<std::string>{CLOTHBENCH_EXAMPLE_ENGINE};
  const cloth::Scene scene = free_seed_scene();
  cloth::SolverOptions so;
  so.integrator = cloth::Integrator::symplectic_euler;
  cloth::MassSpringCloth custom(scene, so);
  ExternalEngine external(options, scene, 1e-4);
  // 0.2 s in frames of 100 steps: the cloth swings down about 0.2 m
  for (int frame = 0; frame < 20; ++frame) {
    custom.advance(1e-4, 100);
    external.advance(1e-4, 100);
  }
  CHECK(external.time() == Approx(custom.time()).epsilon(1e-12));
  CHECK(external.counters().steps == 2000);
  CHECK((external.positions() - custom.positions()).cwiseAbs().maxCoeff() < tol::kExternalRoundOff);
  CHECK((external.velocities() - custom.velocities()).cwiseAbs().maxCoeff() <
        tol::kExternalRoundOffVelocity);
  // the cloth has moved far more than the difference: the comparison is not of two rests
  CHECK((custom.positions() - custom.model().x0).cwiseAbs().maxCoeff() > 0.1);
  // the engine books its dampers' work as the custom engine does
  CHECK(external.dissipated() == Approx(custom.dissipated()).epsilon(1e-6));
}

TEST_CASE("An external engine takes and reports a state exactly", "[external]") {
  // both examples; a 100 x 100 cloth's state (480 kB) is more than a socket holds by default
  // (the harness asks for more where the system allows, else it crosses in pieces)
  const std::string command = GENERATE(std::string("python"), std::string("cpp"));
  const int side = GENERATE(25, 100);
  CAPTURE(command, side);
  ExternalOptions options;
  options.command = command == "python"
                        ? std::vector<std::string>{"/usr/bin/python3", kPythonEngine}
                        : std::vector<std::string>{CLOTHBENCH_EXAMPLE_ENGINE};
  cloth::Scene scene = cloth::seed_scene(side);
  scene.spheres.clear();
  ExternalEngine e(options, scene, 1e-3);
  const int P = side * side;
  cloth::Matrix3X x = cloth::Matrix3X::Random(3, P), v = cloth::Matrix3X::Random(3, P);
  e.set_state(x, v, 0.25);
  CHECK(e.time() == 0.25);
  CHECK(e.positions() == x);
  CHECK(e.velocities() == v);
  e.read_state();
  CHECK(e.positions() == x);
  CHECK(e.velocities() == v);
  // a second state replaces the first one whole
  e.set_state(v, x, 0.5);
  CHECK(e.positions() == v);
  CHECK(e.velocities() == x);
  REQUIRE(e.can_set_state());
}

TEST_CASE("An external program that cannot be run fails with the reason", "[external]") {
  const std::string missing =
      GENERATE(std::string("/no/such/engine"), std::string("clothbench-no-such-engine-on-path"));
  CAPTURE(missing);
  const std::string what = failure_of({{missing}, 1.0});
  CHECK_THAT(what, Catch::Contains("cannot run " + missing) &&
                       Catch::Contains("No such file or directory"));
}

namespace {

/// What the open descriptors of process pid ("self" for this one) refer to, by number
/// ("socket:[123]", a path).
std::map<std::string, std::string> open_files(const std::string& pid) {
  std::map<std::string, std::string> out;
  for (const auto& f : std::filesystem::directory_iterator("/proc/" + pid + "/fd")) {
    std::error_code e;
    const auto target = std::filesystem::read_symlink(f.path(), e);
    if (!e) out[f.path().filename().string()] = target.string();
  }
  return out;
}

}  // namespace

TEST_CASE("External engines started at once inherit only their stdin, stdout and stderr",
          "[external]") {
  // descriptors this process had before (from whatever started the tests) may be inherited
  std::set<std::string> before;
  for (const auto& [fd, target] : open_files("self")) before.insert(target);
  // two engines started from two threads, as -j 2 does
  std::unique_ptr<ExternalEngine> engines[2];
  std::thread starters[2];
  for (int k = 0; k < 2; ++k)
    starters[k] = std::thread([&engines, k] {
      engines[k] = std::make_unique<ExternalEngine>(
          ExternalOptions{{CLOTHBENCH_EXAMPLE_ENGINE}, 10.0}, free_seed_scene(), 1e-3);
    });
  for (std::thread& t : starters) t.join();
  // each child: 0 and 1 one socket, 2 a pipe, nothing else the harness opened (such as the
  // other engine's socket)
  for (const auto& e : engines) {
    REQUIRE(e);
    const auto files = open_files(std::to_string(e->pid()));
    REQUIRE(files.count("0") + files.count("1") + files.count("2") == 3);
    CHECK(files.at("0").rfind("socket:", 0) == 0);
    CHECK(files.at("1") == files.at("0"));
    CHECK(files.at("2").rfind("pipe:", 0) == 0);
    for (const auto& [fd, target] : files)
      if (fd != "0" && fd != "1" && fd != "2") CHECK(before.count(target) == 1);
    e->advance(1e-3, 2);
    CHECK(e->time() == Approx(2e-3));
  }
  CHECK(open_files(std::to_string(engines[0]->pid())).at("0") !=
        open_files(std::to_string(engines[1]->pid())).at("0"));
}

TEST_CASE("An external engine that misbehaves fails with its reason and is reaped", "[external]") {
  struct Case {
    const char* mode;
    const char* reason;  // in the message
  };
  const Case c = GENERATE(
      Case{"crash", "about to crash on purpose"}, Case{"crash", "killed by signal 6"},
      Case{"garbage", "not a protocol frame"}, Case{"wrong-count", "624 particles"},
      Case{"early-exit", "exited with status 4"}, Case{"early-exit", "leaving early"},
      Case{"error", "cannot do this on purpose"}, Case{"bad-version", "protocol version 99"});
  CAPTURE(c.mode);
  const std::string what = failure_of(misbehaving(c.mode));
  CHECK_THAT(what, Catch::Contains(c.reason));
}

TEST_CASE("An external engine that hangs is killed at its step_timeout", "[external]") {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string what = failure_of(misbehaving("hang", 0.5));
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK_THAT(what, Catch::Contains("no answer within its step_timeout"));
  CHECK_THAT(what, Catch::Contains("hanging on purpose"));
  CHECK(waited < 5.0);  // a bound on the harness's wait, not a speed measurement
}

TEST_CASE("An external engine's processes are reaped, also after a failure", "[external]") {
  int pid = 0;
  {
    ExternalEngine e(misbehaving("good"), free_seed_scene(), 1e-3);
    pid = e.pid();
    e.advance(1e-3, 3);
    CHECK(!gone(pid));
  }
  CHECK(gone(pid));
  // an engine that fails is reaped when the failure is thrown
  try {
    ExternalEngine e(misbehaving("hang", 0.3), free_seed_scene(), 1e-3);
    pid = e.pid();
    e.advance(1e-3, 1);
  } catch (const cloth::EngineFailure&) {
  }
  CHECK(gone(pid));
  // an engine that writes far more stderr than a pipe holds is not blocked by it
  ExternalEngine noisy(misbehaving("noisy"), free_seed_scene(), 1e-3);
  noisy.advance(1e-3, 1);
  CHECK(noisy.time() == Approx(1e-3));
}

namespace {

/// A scenario of the free seed scene (15 x 15, 0.1 s) with the custom engine and an external
/// engine running misbehaving_engine.py in mode.
Scenario two_engines(const std::string& mode) {
  const std::string text = R"(
name = "external"
duration = 0.1
frame_interval = 0.01
[cloth]
particles = [15, 15]
size = [4.0, 4.0]
[[constraint]]
select = "corners"
hold = "xyz"
[[engine]]
name = "custom"
kind = "custom"
integrator = "symplectic-euler"
dt = 2e-4
[[engine]]
name = "mine"
kind = "external"
command = ["/usr/bin/python3", ")" +
                           kMisbehaving + R"(", ")" + mode + R"("]
step_timeout = 0.5
dt = 1e-3
)";
  return parse_scenario(text, "<test>", {}, {});
}

}  // namespace

TEST_CASE("A failing external engine fails its own run only", "[external]") {
  ::setenv(reference::kAllowExternalVariable, "1", 1);
  struct Case {
    const char* mode;
    const char* cause;
  };
  const Case c = GENERATE(Case{"crash", "engine failed: "}, Case{"hang", "no answer within"},
                          Case{"nan", "non-finite"}, Case{"good", ""});
  CAPTURE(c.mode);
  RunOptions o;
  o.progress = false;
  const RunResult r = run_scenario(two_engines(c.mode), o);
  REQUIRE(r.runs.size() == 2);
  CHECK(r.runs[0].stable);
  CHECK(r.runs[0].frames.size() == 11);
  CHECK(r.runs[1].stable == (std::string(c.mode) == "good"));
  CHECK_THAT(r.runs[1].cause, Catch::Contains(c.cause));
  // the runner asks for a whole frame (10 steps of 1 ms) in one request: 10 requests in all
  if (std::string(c.mode) == "good") {
    CHECK(r.runs[1].counters.steps == 100);
    CHECK(r.runs[1].counters.force_evals == 10);
  }
}

TEST_CASE("An external engine runs only when allowed", "[external]") {
  ::unsetenv(reference::kAllowExternalVariable);
  RunOptions o;
  o.progress = false;
  CHECK_THROWS_WITH(
      run_scenario(two_engines("good"), o),
      Catch::Contains("--allow-external") && Catch::Contains("CLOTHBENCH_ALLOW_EXTERNAL=1"));
  ::setenv(reference::kAllowExternalVariable, "1", 1);
  CHECK_NOTHROW(run_scenario(two_engines("good"), o));
  ::unsetenv(reference::kAllowExternalVariable);
}

TEST_CASE("An external command's paths are resolved against the scenario's folder",
          "[external][scenario]") {
  test::TempDir dir("external-paths");
  std::filesystem::create_directories(dir.path / "engines");
  std::ofstream(dir.path / "engines" / "mine.py") << "# an engine\n";
  std::ofstream(dir.path / "s.toml") << R"(
[[engine]]
kind = "external"
command = ["python3", "engines/mine.py", "-v", "not/a/file", "/abs/path"]
)";
  const Scenario s = load_scenario((dir.path / "s.toml").string());
  const std::vector<std::string> expected = {
      "python3", (dir.path / "engines" / "mine.py").lexically_normal().string(), "-v", "not/a/file",
      "/abs/path"};
  CHECK(s.engines[0].external.command == expected);
  CHECK(s.engines[0].external.step_timeout == 60.0);
  CHECK_THROWS_WITH(
      parse_scenario("[[engine]]\nkind = \"external\"\ncommand = []\n", "<t>", {}, {}),
      Catch::Contains("a non-empty array of non-empty strings"));
  CHECK_THROWS_WITH(parse_scenario("[[engine]]\nkind = \"external\"\n", "<t>", {}, {}),
                    Catch::Contains("needs a command"));
}

namespace {

/// The CPUs the calling thread may run on.
std::set<int> thread_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  REQUIRE(::sched_getaffinity(0, sizeof set, &set) == 0);
  std::set<int> out;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &set)) out.insert(c);
  return out;
}

/// The CPUs process pid may run on, as the kernel lists them in /proc/PID/status
/// (Cpus_allowed_list: "0-3,6").
std::set<int> process_cpus(int pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::set<int> out;
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("Cpus_allowed_list:", 0) != 0) continue;
    std::istringstream list(line.substr(18));
    for (std::string range; std::getline(list, range, ',');) {
      const size_t dash = range.find('-');
      const int first = std::stoi(range.substr(0, dash));
      const int last = dash == std::string::npos ? first : std::stoi(range.substr(dash + 1));
      for (int c = first; c <= last; ++c) out.insert(c);
    }
  }
  return out;
}

/// True when this system lets a thread set its own CPUs (some restricted containers do not:
/// there share_cpu runs unpinned, and the tests below have nothing to check).
bool pinning_allowed() {
  cpu_set_t set;
  CPU_ZERO(&set);
  return ::sched_getaffinity(0, sizeof set, &set) == 0 &&
         ::sched_setaffinity(0, sizeof set, &set) == 0;
}

ExternalOptions example_engine(bool share_cpu) {
  ExternalOptions o;
  o.command = {CLOTHBENCH_EXAMPLE_ENGINE};
  o.step_timeout = 10.0;
  o.share_cpu = share_cpu;
  return o;
}

}  // namespace

TEST_CASE("With share_cpu an external engine runs on its thread's one CPU until destroyed",
          "[external]") {
  if (!pinning_allowed()) {
    WARN("this system does not let a thread set its CPUs: nothing to check");
    return;
  }
  const std::set<int> before = thread_cpus();
  {
    ExternalEngine e(example_engine(true), free_seed_scene(), 1e-3);
    REQUIRE(e.cpu() >= 0);
    CHECK(before.count(e.cpu()) == 1);
    // the thread and the program may run on that CPU alone, and do
    const std::set<int> one = {e.cpu()};
    CHECK(thread_cpus() == one);
    CHECK(process_cpus(e.pid()) == one);
    e.advance(1e-3, 5);
    CHECK(::sched_getcpu() == e.cpu());
    CHECK(e.time() == Approx(5e-3));
  }
  // the thread has its CPUs back
  CHECK(thread_cpus() == before);
  // without the key neither is pinned: the program has the thread's CPUs
  ExternalEngine unpinned(example_engine(false), free_seed_scene(), 1e-3);
  CHECK(unpinned.cpu() == -1);
  CHECK(process_cpus(unpinned.pid()) == before);
  CHECK(thread_cpus() == before);
}

TEST_CASE("Engines with share_cpu on two threads at once get two CPUs where there are two",
          "[external]") {
  if (!pinning_allowed()) {
    WARN("this system does not let a thread set its CPUs: nothing to check");
    return;
  }
  const std::set<int> allowed = thread_cpus();
  // each thread keeps its engine until both have started, as a -j 2 sweep's runs overlap
  std::atomic<int> started{0};
  int cpus[2] = {-1, -1}, child_cpus[2] = {0, 0};
  bool restored[2] = {false, false};
  std::thread runs[2];
  for (int k = 0; k < 2; ++k)
    runs[k] = std::thread([&, k] {
      const std::set<int> mine = thread_cpus();
      {
        ExternalEngine e(example_engine(true), free_seed_scene(), 1e-3);
        cpus[k] = e.cpu();
        child_cpus[k] = int(process_cpus(e.pid()).size());
        ++started;
        while (started.load() < 2) std::this_thread::yield();
        e.advance(1e-3, 2);
      }
      restored[k] = thread_cpus() == mine;
    });
  for (std::thread& t : runs) t.join();
  for (int k = 0; k < 2; ++k) {
    CHECK(allowed.count(cpus[k]) == 1);
    CHECK(child_cpus[k] == 1);
    CHECK(restored[k]);
  }
  // distinct CPUs while there are enough; with one CPU both share it
  if (allowed.size() >= 2)
    CHECK(cpus[0] != cpus[1]);
  else
    CHECK(cpus[0] == cpus[1]);
}

namespace {

/// stability.csv of a blow-up search with 2 jobs over two C++ example engines (15 x 15 free
/// seed scene, 0.05 s horizon), with share_cpu as given.
std::string stability_csv(bool share_cpu) {
  ::setenv(reference::kAllowExternalVariable, "1", 1);
  std::string text = R"(
name = "share"
duration = 0.05
frame_interval = 0.05
[cloth]
particles = [15, 15]
size = [4.0, 4.0]
[[constraint]]
select = "corners"
hold = "xyz"
)";
  for (const char* name : {"a", "b"})
    text += std::string("[[engine]]\nname = \"") + name + "\"\nkind = \"external\"\ncommand = [\"" +
            CLOTHBENCH_EXAMPLE_ENGINE + "\"]\nshare_cpu = " + (share_cpu ? "true" : "false") +
            "\ndt = 1e-3\n";
  const Scenario sc = parse_scenario(text, "<test>", {}, {});
  test::TempDir dir(share_cpu ? "share-cpu-on" : "share-cpu-off");
  StabilityOptions o;
  o.out_dir = dir.str();
  o.jobs = 2;
  o.progress = false;
  o.method = StabilityMethod::blowup;
  const std::vector<StabilityRow> rows = run_stability(sc, o);
  ::unsetenv(reference::kAllowExternalVariable);
  REQUIRE(rows.size() == 2);
  CHECK(std::isfinite(rows[0].first_unstable_dt));
  std::ifstream in(dir.path / "stability.csv");
  std::ostringstream all;
  all << in.rdbuf();
  return all.str();
}

}  // namespace

TEST_CASE("A -j 2 stability sweep with share_cpu writes what it writes without",
          "[external][stability]") {
  const std::string off = stability_csv(false), on = stability_csv(true);
  CHECK(off.find("\na,") != std::string::npos);
  CHECK(on == off);
}

TEST_CASE("share_cpu is an external engine's key, kept by the scenario writer",
          "[external][scenario]") {
  const std::string engine = std::string("[[engine]]\nkind = \"external\"\ncommand = [\"") +
                             CLOTHBENCH_EXAMPLE_ENGINE + "\"]\n";
  CHECK_FALSE(parse_scenario(engine, "<t>", {}, {}).engines[0].external.share_cpu);
  const Scenario on = parse_scenario(engine + "share_cpu = true\n", "<t>", {}, {});
  CHECK(on.engines[0].external.share_cpu);
  CHECK(parse_scenario(scenario_to_toml(on), "<t>", {}, {}).engines[0].external.share_cpu);
  CHECK_THROWS_WITH(parse_scenario(engine + "share_cpu = 1\n", "<t>", {}, {}),
                    Catch::Contains("share_cpu") && Catch::Contains("true or false"));
  // other kinds refuse it, naming the kind it belongs to
  const std::string kind = GENERATE(std::string("custom"), std::string("bullet-softbody"));
  CAPTURE(kind);
  CHECK_THROWS_WITH(
      parse_scenario("[[engine]]\nkind = \"" + kind + "\"\nshare_cpu = true\n", "<t>", {}, {}),
      Catch::Contains("share_cpu") && Catch::Contains("applies only to external engines") &&
          Catch::Contains("this one is " + kind));
}
