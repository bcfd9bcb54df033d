#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "harness/io/csv_writer.hpp"
#include "harness/io/staged_folder.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_writer.hpp"
#include "temp_dir.hpp"
#include "test_scenes.hpp"

using namespace clothbench;
namespace fs = std::filesystem;

namespace {

// a small flag swinging above a sphere it never reaches; the second rk4 engine is an exact
// copy of the reference, so its divergence must be exactly zero
const char* kSmallScenario = R"(
name = "small"
description = "test scene"
duration = 0.3
frame_interval = 0.01
snapshot_interval = 0.1
reference = "rk4"
[cloth]
particles = [6, 5]
size = [0.5, 0.4]
center = [0.0, 1.0, 0.0]
plane = "xz"
particle_mass = 0.01
stiffness = { structural = 50.0, shear = 50.0, bend = 5.0 }
damping = 0.05
[[constraint]]
select = "edge:u0"
hold = "xyz"
[[sphere]]
center = [0.0, -5.0, 0.0]
radius = 0.5
[[engine]]
name = "rk4"
integrator = "rk4"
dt = 1e-4
[[engine]]
name = "rk4-copy"
integrator = "rk4"
dt = 1e-4
[[engine]]
name = "symplectic"
integrator = "symplectic-euler"
dt = 5e-4
[[engine]]
name = "explicit-big-step"
integrator = "explicit-euler"
dt = 1e-2
)";

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int col(const std::string& name) const {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    FAIL("no column " << name);
    return -1;
  }
  double num(size_t row, const std::string& name) const {
    return std::stod(rows[row][static_cast<size_t>(col(name))]);
  }
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, ',')) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

Csv read_csv(const fs::path& p) {
  std::ifstream in(p);
  REQUIRE(in.good());
  Csv c;
  std::string line;
  std::getline(in, line);
  c.header = split(line);
  while (std::getline(in, line)) {
    c.rows.push_back(split(line));
    REQUIRE(c.rows.back().size() == c.header.size());
  }
  return c;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

RunResult run_small(const std::vector<std::string>& overrides = {}) {
  RunOptions o;
  o.progress = false;
  return run_scenario(parse_scenario(kSmallScenario, "small.toml", overrides), o);
}

}  // namespace

TEST_CASE("an end-to-end run writes every column with consistent values", "[scenario][runner]") {
  const clothbench::test::TempDir scratch("runner-e2e");
  const fs::path& dir = scratch.path;
  write_run(run_small(), dir.string());

  const Csv frames = read_csv(dir / "frames.csv");
  CHECK(frames.header == std::vector<std::string>{"engine",
                                                  "t",
                                                  "kinetic",
                                                  "gravity_potential",
                                                  "elastic_potential",
                                                  "dissipated",
                                                  "contact_work",
                                                  "collider_work",
                                                  "unbooked",
                                                  "handle_work",
                                                  "total_energy",
                                                  "energy_error",
                                                  "max_strain",
                                                  "mean_strain",
                                                  "com_x",
                                                  "com_y",
                                                  "com_z",
                                                  "min_y",
                                                  "max_penetration",
                                                  "shadow_area",
                                                  "stable",
                                                  "contacts",
                                                  "contact_fx",
                                                  "contact_fy",
                                                  "contact_fz",
                                                  "max_stretch",
                                                  "max_compression",
                                                  "self_intersections",
                                                  "min_self_distance"});
  std::map<std::string, int> rows_per_engine;
  double e0 = 0, rk4_worst = 0;
  for (size_t r = 0; r < frames.rows.size(); ++r) {
    const std::string engine = frames.rows[r][0];
    const int k = rows_per_engine[engine]++;
    const bool stable = frames.num(r, "stable") == 1.0;
    if (!stable) continue;
    CHECK(frames.num(r, "t") == Approx(0.01 * k).margin(1e-12));
    const double total = frames.num(r, "kinetic") + frames.num(r, "gravity_potential") +
                         frames.num(r, "elastic_potential");
    CHECK(frames.num(r, "total_energy") == Approx(total).epsilon(1e-12));
    if (k == 0) e0 = total;
    CHECK(frames.num(r, "energy_error") ==
          Approx(total + frames.num(r, "dissipated") - frames.num(r, "contact_work") -
                 frames.num(r, "collider_work") - frames.num(r, "handle_work") -
                 frames.num(r, "unbooked") - e0)
              .margin(1e-9));
    CHECK(frames.num(r, "dissipated") >= 0.0);
    // the sphere is out of reach: no contact work, and a custom engine books everything
    CHECK(frames.num(r, "contact_work") == 0.0);
    CHECK(frames.num(r, "collider_work") == 0.0);
    CHECK(frames.num(r, "unbooked") == 0.0);
    CHECK(frames.num(r, "handle_work") == 0.0);  // no handle
    CHECK(frames.num(r, "max_strain") >= frames.num(r, "mean_strain"));
    CHECK(frames.num(r, "min_y") <= frames.num(r, "com_y"));
    CHECK(frames.num(r, "max_penetration") == 0.0);
    // the shadow of a flat 0.5 x 0.4 m cloth, less as it swings down
    CHECK(frames.num(r, "shadow_area") <= 0.2 * 1.01);
    CHECK(frames.num(r, "shadow_area") > 0.0);
    if (engine == "rk4") rk4_worst = std::max(rk4_worst, std::abs(frames.num(r, "energy_error")));
  }
  CHECK(rows_per_engine["rk4"] == 31);
  CHECK(rows_per_engine["symplectic"] == 31);
  // the cloth falls through about 0.2 m: 30 particles * 0.01 kg * 9.8 * 0.2 ~ 0.6 J moves
  INFO("rk4 worst energy error " << rk4_worst << " J");
  CHECK(rk4_worst < 1e-8);
  CHECK(frames.num(0, "shadow_area") == Approx(0.2).epsilon(0.01));

  // the big explicit step blows up: its rows end with stable = 0, the others carry on
  const Csv summary = read_csv(dir / "summary.csv");
  REQUIRE(summary.rows.size() == 4);
  CHECK(summary.rows[3][summary.col("stable")] == "0");
  CHECK(std::stod(summary.rows[3][summary.col("blowup_t")]) > 0.0);
  CHECK(summary.rows[0][summary.col("blowup_t")].empty());
  CHECK(frames.rows.back()[frames.col("stable")] == "0");
  CHECK(summary.rows[0][summary.col("integrator")] == "rk4");
  CHECK(summary.num(0, "force_evals") == 4 * 3000);
  CHECK(summary.num(2, "steps") == 600);
  // no support under the cloth: no drape coefficient
  CHECK(summary.rows[0][summary.col("drape_coefficient")].empty());
  // the cost and comparison columns agree with each other and with the other files
  for (size_t r = 0; r < summary.rows.size(); ++r) {
    CHECK(summary.rows[r][summary.col("kind")] == "custom");
    CHECK(summary.num(r, "wall_s") > 0.0);
    CHECK(summary.num(r, "us_per_step") ==
          Approx(1e6 * summary.num(r, "wall_s") / summary.num(r, "steps")).epsilon(1e-9));
    CHECK(summary.num(r, "max_energy_error") >= 0.0);
  }
  CHECK(summary.num(0, "dt") == 1e-4);
  CHECK(summary.num(3, "steps") < 30);  // stopped at the blow-up
  // a swinging cloth is far from equilibrium, and it moves
  CHECK(summary.num(0, "static_residual") > 0.1);
  CHECK(summary.num(0, "final_kinetic") > 0.0);
  CHECK(summary.num(0, "final_rms_vs_reference") == 0.0);  // the reference itself
  CHECK(summary.num(1, "final_rms_vs_reference") == 0.0);  // its exact copy
  CHECK(summary.num(2, "max_rms_vs_reference") >= summary.num(2, "final_rms_vs_reference"));
  CHECK(summary.num(2, "max_rms_vs_reference") > 0.0);

  // divergence: none for the reference, exactly zero for its copy, small for symplectic
  const Csv div = read_csv(dir / "divergence.csv");
  CHECK(div.header == std::vector<std::string>{"engine", "reference", "t", "rms_distance",
                                               "max_distance", "com_distance", "energy_difference",
                                               "shadow_area_difference"});
  double symplectic_worst = 0;
  for (size_t r = 0; r < div.rows.size(); ++r) {
    CHECK(div.rows[r][0] != "rk4");
    CHECK(div.rows[r][1] == "rk4");
    if (div.rows[r][0] == "rk4-copy") {
      CHECK(div.num(r, "rms_distance") == 0.0);
      CHECK(div.num(r, "max_distance") == 0.0);
      CHECK(div.num(r, "energy_difference") == 0.0);
    }
    if (div.rows[r][0] == "symplectic") {
      CHECK(div.num(r, "max_distance") >= div.num(r, "rms_distance"));
      // the centre of mass is the mean position: its distance is at most the RMS distance
      CHECK(div.num(r, "com_distance") <= div.num(r, "rms_distance") + 1e-15);
      symplectic_worst = std::max(symplectic_worst, div.num(r, "rms_distance"));
    }
  }
  CHECK(symplectic_worst > 0.0);
  CHECK(symplectic_worst < 0.01);

  // snapshots at 0, 0.1, 0.2, 0.3 s, every particle, matching the final frame's centre of mass
  const Csv snaps = read_csv(dir / "snapshots.csv");
  std::map<std::string, int> snap_rows;
  double com_y = 0;
  for (size_t r = 0; r < snaps.rows.size(); ++r) {
    ++snap_rows[snaps.rows[r][0]];
    if (snaps.rows[r][0] == "rk4" && std::abs(snaps.num(r, "t") - 0.3) < 1e-12)
      com_y += snaps.num(r, "y") / 30.0;
  }
  CHECK(snap_rows["rk4"] == 4 * 30);
  CHECK(com_y == Approx(frames.num(30, "com_y")).epsilon(1e-12));

  // the resolved scenario reruns the same scene; run.json says what made it
  const Scenario again = load_scenario((dir / "scenario.toml").string());
  CHECK(scenario_to_toml(again) == slurp(dir / "scenario.toml"));
  const std::string info = slurp(dir / "run.json");
  CHECK(info.find("\"git_commit\"") != std::string::npos);
  CHECK(info.find("\"compiler\"") != std::string::npos);
}

TEST_CASE("two runs give byte-identical CSVs apart from timing columns", "[runner]") {
  const clothbench::test::TempDir scratch_a("runner-det-a"), scratch_b("runner-det-b");
  const fs::path &a = scratch_a.path, &b = scratch_b.path;
  write_run(run_small(), a.string());
  write_run(run_small(), b.string());
  for (const char* f : {"frames.csv", "divergence.csv", "snapshots.csv", "scenario.toml"})
    CHECK(slurp(a / f) == slurp(b / f));
  Csv sa = read_csv(a / "summary.csv"), sb = read_csv(b / "summary.csv");
  for (Csv* s : {&sa, &sb})
    for (auto& row : s->rows)
      row[static_cast<size_t>(s->col("wall_s"))] = row[static_cast<size_t>(s->col("us_per_step"))] =
          "";
  CHECK(sa.rows == sb.rows);
}

TEST_CASE("bad input and interruption leave no output behind", "[runner][scenario]") {
  // a bad override is refused before anything runs
  CHECK_THROWS_AS(run_small({"engine.rk4.dt=-1"}), ScenarioError);
  // an engine filter naming no engine
  RunOptions o;
  o.progress = false;
  o.engines = {"nope"};
  CHECK_THROWS_WITH(run_scenario(parse_scenario(kSmallScenario, "small.toml"), o),
                    Catch::Contains("--engine nope") && Catch::Contains("rk4-copy"));
  // an interrupted run stops with Interrupted, before anything could be written
  interrupt_requested() = true;
  CHECK_THROWS_AS(run_small(), Interrupted);
  interrupt_requested() = false;
  // an unwritable output folder is a clear error
  CHECK_THROWS_WITH(write_run(run_small({"duration=0.02"}), "/proc/clothbench"),
                    Catch::Contains("/proc/clothbench"));
}

TEST_CASE("a CSV appears only when committed, and an abandoned one leaves nothing", "[runner]") {
  const clothbench::test::TempDir scratch("runner-atomic");
  const fs::path& dir = scratch.path;
  fs::create_directories(dir);
  const fs::path target = dir / "table.csv";
  {
    // rows written, then the writer is abandoned (an error or an interrupt unwinds past it)
    CsvWriter w(target.string(), {"a", "b"});
    w.add(1).add(2).end_row();
    CHECK_FALSE(fs::exists(target));  // not visible while being written
    CHECK(fs::directory_iterator(dir) != fs::directory_iterator());  // its temporary file is
  }
  CHECK(fs::directory_iterator(dir) == fs::directory_iterator());  // nothing is left behind
  {
    CsvWriter w(target.string(), {"a", "b"});
    w.add(1).add(2).end_row();
    w.commit();
  }
  CHECK(slurp(target) == "a,b\n1,2\n");
  CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);
}

TEST_CASE("an engine filter runs the chosen engines and the reference", "[runner]") {
  RunOptions o;
  o.progress = false;
  o.engines = {"symplectic"};
  const RunResult r = run_scenario(parse_scenario(kSmallScenario, "small.toml"), o);
  REQUIRE(r.runs.size() == 2);
  CHECK(r.runs[static_cast<size_t>(r.reference)].spec.name == "rk4");
}

TEST_CASE("shadow area of a flat grid is its area; a fold is not counted twice", "[runner]") {
  cloth::Scene s;
  s.cloth.nu = 9;
  s.cloth.nv = 5;
  s.cloth.size_u = 2.0;
  s.cloth.size_v = 1.0;
  const cloth::Model m = cloth::build_model(s);
  const Eigen::Vector3d g(0, -9.8, 0);
  // raster error is about half the perimeter's cells: 6 m * (2 m / 512) / 2 ~ 0.012 m^2
  CHECK(shadow_area(m, g, m.x0) == Approx(2.0).margin(0.012));
  // fold the cloth in half along x = 0: the shadow halves
  cloth::Matrix3X folded = m.x0;
  for (Eigen::Index p = 0; p < folded.cols(); ++p)
    if (folded(0, p) > 0) {
      folded(1, p) += 0.1 + 0.01 * folded(0, p);
      folded(0, p) = -folded(0, p);
    }
  CHECK(shadow_area(m, g, folded) == Approx(1.0).margin(0.012));
}

TEST_CASE("the drape coefficient is 1 for a flat cloth and falls as it drapes", "[runner]") {
  // a small Cusick table: a 0.6 m square over a held disk of radius 0.15 m
  const char* table = R"(
name = "small_table"
duration = 0.5
frame_interval = 0.01
[cloth]
particles = [13, 13]
size = [0.6, 0.6]
center = [0.0, 0.5, 0.0]
total_mass = 0.072
stiffness = { structural = 50.0, shear = 50.0, bend = 5.0 }
damping = 0.01
[[constraint]]
select = "disk"
hold = "y"
center = [0.0, 0.0]
radius = 0.15
[[engine]]
name = "rk4"
dt = 1e-3
)";
  RunOptions o;
  o.progress = false;
  auto coefficient = [&](const std::string& duration) {
    const RunResult r =
        run_scenario(parse_scenario(table, "table.toml", {"duration=" + duration}), o);
    return final_drape_coefficient(r, r.runs[0]);
  };
  // flat: the shadow is the whole cloth, (A - S) / (A - S) = 1 up to the shadow's raster error
  CHECK(coefficient("0.01") == Approx(1.0).margin(0.02));
  // draped: the skirt hangs down, its shadow shrinks toward the support
  const double draped = coefficient("0.5");
  CHECK(draped < 0.9);
  CHECK(draped > 0.0);
}

TEST_CASE("the static residual is 0 at an equilibrium and not away from one", "[runner]") {
  // a hanging chain at its discrete statics: the spring above particle j carries the j + 1
  // particles below it, stretched by (j + 1) m g / k
  const int n = 10;
  const double m = 0.1, k = 100.0, l = 0.1, g = 9.8;
  const cloth::Model chain = cloth::build_model(clothbench::test::chain(n, m, k, l, 5.0, g));
  cloth::Matrix3X x = chain.x0;
  for (int j = n - 1; j >= 0; --j) x(1, j) = x(1, j + 1) - (l + (j + 1) * m * g / k);
  const cloth::Matrix3X rest = cloth::Matrix3X::Zero(3, x.cols());
  CHECK(static_residual(chain, 0.0, x, rest) < 1e-12);
  // at the rest lengths nothing holds the particles up: the net force is the weight
  CHECK(static_residual(chain, 0.0, chain.x0, rest) == Approx(1.0).epsilon(1e-12));
  // a moving chain at its statics feels its dampers
  cloth::Matrix3X v = rest;
  v(1, 0) = 1.0;
  CHECK(static_residual(chain, 0.0, x, v) > 0.1);

  // a loose particle resting on a sphere 30 degrees from its pole: the sphere carries the
  // normal part of its weight; sin 30 = 0.5 of it is left without friction, none with
  // mu = 1 > tan 30
  cloth::Scene s = clothbench::test::small_cloth(2, 0.0, 0.0);
  s.spheres.push_back(cloth::Sphere{});
  cloth::Model dust = cloth::build_model(s);
  cloth::Matrix3X p = dust.x0;
  const double shell = 1.0 + s.spheres[0].margin, a = M_PI / 6;
  for (int q = 0; q < 4; ++q) p.col(q) = shell * Eigen::Vector3d(std::sin(a), std::cos(a), 0.0);
  const cloth::Matrix3X still = cloth::Matrix3X::Zero(3, 4);
  dust.free.setOnes();
  CHECK(static_residual(dust, 0.0, p, still) == Approx(0.5).epsilon(1e-12));
  dust.spheres[0].friction = 1.0;
  CHECK(static_residual(dust, 0.0, p, still) < 1e-12);
}

TEST_CASE("a run's files replace an older run's all at once, keeping the folder's other files",
          "[runner]") {
  const clothbench::test::TempDir scratch("runner-staged");
  const fs::path dir = scratch.path / "out";
  write_run(run_small({"duration=0.02"}), dir.string());
  const std::string old_scenario = slurp(dir / "scenario.toml");
  {  // a user's note and a folder of plots beside the run, and a stage a killed run left
    std::ofstream(dir / "notes.txt") << "mine\n";
    fs::create_directories(dir / "plots");
    std::ofstream(dir / "plots" / "a.png") << "png\n";
    fs::create_directories(scratch.path / ".out.clothbench-new-999999");
  }
  {  // an abandoned stage (an error or an interrupt before its commit) changes nothing
    StagedFolder staged(dir.string());
    std::ofstream(staged.path() + "summary.csv") << "half\n";
    CHECK(fs::exists(staged.path()));
  }
  CHECK(slurp(dir / "scenario.toml") == old_scenario);
  write_run(run_small({"duration=0.04"}), dir.string());
  // every run file is the new run's: the scenario and summary agree on the duration
  CHECK(slurp(dir / "scenario.toml") != old_scenario);
  CHECK(slurp(dir / "scenario.toml").find("duration = 0.04") != std::string::npos);
  const Csv summary = read_csv(dir / "summary.csv");
  const Csv frames = read_csv(dir / "frames.csv");
  double last_t = 0;
  for (size_t r = 0; r < frames.rows.size(); ++r) last_t = std::max(last_t, frames.num(r, "t"));
  CHECK(last_t == Approx(0.04));
  CHECK(!summary.rows.empty());
  // the folder's other files stay, and no stage is left beside it
  CHECK(slurp(dir / "notes.txt") == "mine\n");
  CHECK(slurp(dir / "plots" / "a.png") == "png\n");
  for (const auto& e : fs::directory_iterator(scratch.path))
    CHECK(e.path().filename().string().find("clothbench-new") == std::string::npos);
}

TEST_CASE("a run's trajectory holds every engine's positions every animation_interval",
          "[runner]") {
  const clothbench::test::TempDir scratch("runner-trajectory");
  const fs::path& dir = scratch.path;
  const RunResult r = run_small({"animation_interval=0.05"});
  write_run(r, dir.string());
  const fs::path t = dir / "trajectory";
  const std::string index = slurp(t / "trajectory.json");
  CHECK(index.find("\"interval\": 0.05,") != std::string::npos);
  CHECK(index.find("\"frames\": 7,") != std::string::npos);  // 0, 0.05, ..., 0.3 s
  for (const EngineRun& run : r.runs) {
    const std::string npy = slurp(t / (run.spec.name + ".npy"));
    REQUIRE(npy.size() > 10);
    CHECK(npy.compare(0, 6, "\x93NUMPY") == 0);
    const size_t header =
        10 + static_cast<unsigned char>(npy[8]) + 256 * static_cast<unsigned char>(npy[9]);
    CHECK(header % 64 == 0);
    // frames before a blow-up only, each 6 x 5 particles by 3 float32
    size_t frames = 0;
    for (size_t k = 0; k < run.frames.size() && run.frames[k].stable; k += 5) ++frames;
    CHECK(npy.size() == header + frames * 30 * 3 * sizeof(float));
    CHECK(npy.find("'shape': (" + std::to_string(frames) + ", 30, 3,)") != std::string::npos);
    if (frames < 2) continue;
    // frame 1 is the logged frame at t = 0.05 s, as float32
    float x = 0;
    std::memcpy(&x, npy.data() + header + 30 * 3 * sizeof(float) + 7 * 3 * sizeof(float) + 4,
                sizeof x);
    CHECK(x == static_cast<float>(run.positions[5](1, 7)));
  }
  // explicit-big-step blows up, so its trajectory stops early; the others run to the end
  CHECK(slurp(t / "explicit-big-step.npy").size() < slurp(t / "rk4.npy").size());
}

TEST_CASE("animation_interval = 0 writes no trajectory and a rerun leaves none stale", "[runner]") {
  const clothbench::test::TempDir scratch("runner-no-trajectory");
  const fs::path t = scratch.path / "trajectory";
  write_run(run_small({"animation_interval=0"}), scratch.path.string());
  CHECK(fs::exists(scratch.path / "frames.csv"));
  CHECK_FALSE(fs::exists(t));
  // every engine, then only the reference and one other: the others' files go
  write_run(run_small(), scratch.path.string());
  CHECK(fs::exists(t / "symplectic.npy"));
  RunOptions o;
  o.progress = false;
  o.engines = {"rk4-copy"};
  write_run(run_scenario(parse_scenario(kSmallScenario, "small.toml"), o), scratch.path.string());
  CHECK(fs::exists(t / "rk4.npy"));
  CHECK(fs::exists(t / "rk4-copy.npy"));
  CHECK_FALSE(fs::exists(t / "symplectic.npy"));
  // and a run without trajectories removes the folder
  write_run(run_small({"animation_interval=0"}), scratch.path.string());
  CHECK_FALSE(fs::exists(t));
}

TEST_CASE("a cantilever test writes tests.csv, and a run without one leaves none behind",
          "[runner]") {
  const clothbench::test::TempDir scratch("runner-tests-csv");
  const fs::path& dir = scratch.path;
  RunOptions o;
  o.progress = false;
  const Scenario sc = load_scenario(
      std::string(CLOTHBENCH_SOURCE_DIR) + "/scenarios/fabric/cantilever.toml", {}, {"custom-rk4"});
  write_run(run_scenario(sc, o), dir.string());
  const Csv tests = read_csv(dir / "tests.csv");
  CHECK(tests.header == std::vector<std::string>{"engine", "metric", "value", "unit"});
  // six of the fixed overhang, three of the standard's rule (the scene asks for it)
  REQUIRE(tests.rows.size() == 9);
  std::map<std::string, double> value;
  for (const auto& row : tests.rows) {
    CHECK(row[0] == "custom-rk4");
    value[row[1]] = std::stod(row[2]);
  }
  // the scene's geometry: 100 mm over the edge; a strip that bent but does not hang
  CHECK(value["overhang"] == Approx(0.1).epsilon(1e-12));
  CHECK(value["chord_angle"] > 0);
  CHECK(value["chord_angle"] < 83.9);
  CHECK(value["tip_deflection"] < 0.1);
  // flexural rigidity = areal density x g x c^3 (200 g/m^2, g = 9.8 m/s^2)
  CHECK(value["flexural_rigidity"] ==
        Approx(0.2 * 9.8 * std::pow(value["bending_length"], 3)).epsilon(1e-9));
  // the standard's c is half its overhang, shorter than the scene's, and every settle is listed
  CHECK(value["bending_length_standard"] == Approx(value["standard_overhang"] / 2));
  CHECK(value["standard_overhang"] < 0.1);
  const Csv settles = read_csv(dir / "overhangs.csv");
  CHECK(double(settles.rows.size()) == value["standard_settles"]);
  // a scenario without [test] owns the files too: the older run's tests.csv goes
  write_run(run_small(), dir.string());
  CHECK_FALSE(fs::exists(dir / "tests.csv"));
  CHECK_FALSE(fs::exists(dir / "overhangs.csv"));
}

TEST_CASE("a drape test's coefficient in tests.csv is summary.csv's, and its folds are counted",
          "[runner][drape]") {
  const clothbench::test::TempDir scratch("runner-drape-csv");
  const fs::path& dir = scratch.path;
  RunOptions o;
  o.progress = false;
  const Scenario sc =
      load_scenario(std::string(CLOTHBENCH_SOURCE_DIR) + "/scenarios/cusick_drape.toml",
                    {"duration=1.0"}, {"custom-implicit-euler"});
  write_run(run_scenario(sc, o), dir.string());
  // per engine (the reference, custom-rk4, runs too)
  const Csv tests = read_csv(dir / "tests.csv");
  std::map<std::string, std::map<std::string, double>> value;
  for (const auto& row : tests.rows) value[row[0]][row[1]] = std::stod(row[2]);
  const Csv summary = read_csv(dir / "summary.csv");
  const size_t dc =
      size_t(std::find(summary.header.begin(), summary.header.end(), "drape_coefficient") -
             summary.header.begin());
  REQUIRE(dc < summary.header.size());
  REQUIRE(summary.rows.size() == 2);
  for (const auto& row : summary.rows) {
    INFO(row[0]);
    CHECK(value[row[0]]["drape_coefficient"] == Approx(std::stod(row[dc])).epsilon(1e-12));
    // a hanging specimen folds (a flat one would have none); its outline lies between the
    // support's 9 cm and the specimen's 15 cm
    CHECK(value[row[0]]["folds"] >= 3);
    CHECK(value[row[0]]["min_radius"] > 0.09);
    CHECK(value[row[0]]["max_radius"] < 0.15);
  }
}
