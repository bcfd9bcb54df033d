#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cloth/analysis/linear_stability.hpp"
#include "cloth/model/integrator.hpp"
#include "cloth/model/model.hpp"
#include "harness/io/user_error.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/sweeps/accuracy_plan.hpp"
#include "harness/sweeps/accuracy_sweep.hpp"
#include "harness/sweeps/sweep.hpp"
#include "temp_dir.hpp"
#include "tolerances.hpp"

using namespace clothbench;
namespace fs = std::filesystem;

namespace {

// a soft 5 x 5 cloth, 1 m square, swinging from the two corners of its edge v = 0, no
// contact: smooth motion, so every integrator is in its asymptotic range at these steps
const char* kSwing = R"(
name = "swing"
duration = 0.2
frame_interval = 0.02
reference = "custom"
[cloth]
particles = [5, 5]
size = [1.0, 1.0]
center = [0.0, 0.0, 0.0]
plane = "xz"
particle_mass = 0.1
stiffness = { structural = 20.0, shear = 20.0, bend = 20.0 }
damping = 0.5
[[constraint]]
select = "indices"
list = [[0, 0], [4, 0]]
hold = "xyz"
[[engine]]
name = "custom"
integrator = "rk4"
dt = 4e-3
)";

// the same cloth, 2.5 kg, held along its edge v = 0 (a selection that carries over to any
// grid): it swings down from the horizontal like a flap on a hinge
const std::vector<std::string> kFlap = {"name=flap", "duration=0.5", "cloth.total_mass=2.5",
                                        "constraint.0={ select = \"edge:v0\", hold = \"xyz\" }",
                                        "engine.custom.dt=1e-3"};

struct TempDir : clothbench::test::TempDir {
  explicit TempDir(const std::string& name) : clothbench::test::TempDir("accuracy-" + name) {}
};

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  size_t col(const std::string& name) const {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    FAIL("no column " << name);
    return 0;
  }
};

// an independent reader: fields split at commas, a quoted field kept whole
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted)
      out.emplace_back();
    else
      out.back() += c;
  }
  return out;
}

Csv read_csv(const fs::path& p) {
  Csv csv;
  std::ifstream in(p);
  REQUIRE(in);
  std::string line;
  std::getline(in, line);
  csv.header = split(line);
  while (std::getline(in, line)) csv.rows.push_back(split(line));
  return csv;
}

AccuracyOptions quick_options(const std::string& out) {
  AccuracyOptions o;
  o.out_dir = out;
  o.repeats = 1;  // wall time is not what these tests measure
  o.jobs = 2;
  o.progress = false;
  return o;
}

/// work_precision.csv without the wall-time columns, which vary from run to run.
std::vector<std::vector<std::string>> without_wall_time(const Csv& csv) {
  const size_t a = csv.col("wall_s"), b = csv.col("wall_s_per_sim_s");
  std::vector<std::vector<std::string>> out;
  for (auto row : csv.rows) {
    row.erase(row.begin() + static_cast<std::ptrdiff_t>(std::max(a, b)));
    row.erase(row.begin() + static_cast<std::ptrdiff_t>(std::min(a, b)));
    out.push_back(row);
  }
  return out;
}

}  // namespace

TEST_CASE("accuracy sweep: fitted orders match each integrator's", "[sweep]") {
  TempDir dir("orders");
  const Scenario sc = parse_scenario(kSwing, "swing.toml");
  const AccuracyReport report = run_accuracy(sc, quick_options(dir.str()));

  // 6 integrators x 4 halvings of 4e-3 s, against rk4 at 5e-4 / 4
  REQUIRE(report.rows.size() == cloth::all_integrators().size() * 4);
  CHECK(report.reference.dt == Approx(1.25e-4).epsilon(1e-12));
  CHECK(report.reference.error_floor < 1e-8);
  REQUIRE(report.convergence.size() == cloth::all_integrators().size());
  for (const ConvergenceFit& fit : report.convergence) {
    const auto integrator = cloth::parse_integrator(fit.integrator);
    REQUIRE(integrator);
    INFO(fit.integrator << ": order " << fit.order << " over " << fit.points << " points");
    CHECK(fit.points == 4);
    CHECK(fit.order == Approx(cloth::integrator_order(*integrator)).margin(tol::kOrderMargin));
  }
  for (const AccuracyRow& r : report.rows) {
    CHECK(r.stable);
    CHECK(r.error_max >= r.error_final);
    CHECK(r.force_evals > 0);
  }

  // the files say the same, with the reference named
  const Csv conv = read_csv(dir.path / "convergence.csv");
  CHECK(conv.header == std::vector<std::string>{"engine", "integrator", "order", "points"});
  CHECK(conv.rows.size() == report.convergence.size());
  const Csv wp = read_csv(dir.path / "work_precision.csv");
  CHECK(wp.header == std::vector<std::string>{"engine", "integrator", "dt", "stable", "error_final",
                                              "error_max", "wall_s", "wall_s_per_sim_s",
                                              "force_evals", "cg_iterations", "rerun"});
  CHECK(wp.rows.size() == report.rows.size());
  CHECK(wp.rows[0][wp.col("rerun")] ==
        "--set engine.custom.integrator=explicit-euler --set engine.custom.dt=0.004");
  const Csv ref = read_csv(dir.path / "reference.csv");
  REQUIRE(ref.rows.size() == 1);
  CHECK(ref.rows[0][ref.col("integrator")] == "rk4");
  CHECK(std::stod(ref.rows[0][ref.col("dt")]) == report.reference.dt);
  CHECK_FALSE(fs::exists(dir.path / "recommendation.csv"));  // no tolerance given
}

TEST_CASE("accuracy sweep: the recommendation is the cheapest row within the tolerance",
          "[sweep]") {
  TempDir dir("recommend");
  const Scenario sc = parse_scenario(kSwing, "swing.toml");
  AccuracyOptions o = quick_options(dir.str());
  o.tolerance = 1e-4;  // m: met by some configurations and not by others
  const AccuracyReport report = run_accuracy(sc, o);

  // the cheapest qualifying row, found from the file alone: counted work (the grid is the
  // same for every row), then error, then file order; wall time plays no part
  const Csv wp = read_csv(dir.path / "work_precision.csv");
  const std::vector<std::string>* best = nullptr;
  int qualifying = 0;
  const auto cost = [&](const std::vector<std::string>& r) {
    return std::make_pair(double(std::stoll(r[wp.col("force_evals")])) +
                              kCgIterationCost * double(std::stoll(r[wp.col("cg_iterations")])),
                          std::stod(r[wp.col("error_max")]));
  };
  for (const auto& r : wp.rows) {
    if (r[wp.col("stable")] != "1" || r[wp.col("error_max")].empty()) continue;
    if (std::stod(r[wp.col("error_max")]) > o.tolerance) continue;
    ++qualifying;
    if (!best || cost(r) < cost(*best)) best = &r;
  }
  REQUIRE(best);
  CHECK(qualifying > 0);
  CHECK(qualifying < static_cast<int>(wp.rows.size()));

  const Csv rec = read_csv(dir.path / "recommendation.csv");
  CHECK(rec.header == std::vector<std::string>{"scope", "engine", "integrator", "dt", "error_max",
                                               "wall_s_per_sim_s", "tolerance", "cost"});
  REQUIRE(rec.rows.size() == 2);  // the one engine, then overall
  for (const auto& r : rec.rows) {
    INFO(r[rec.col("scope")]);
    CHECK(r[rec.col("engine")] == (*best)[wp.col("engine")]);
    CHECK(r[rec.col("integrator")] == (*best)[wp.col("integrator")]);
    CHECK(r[rec.col("dt")] == (*best)[wp.col("dt")]);
    CHECK(r[rec.col("error_max")] == (*best)[wp.col("error_max")]);
    CHECK(std::stod(r[rec.col("tolerance")]) == o.tolerance);
    CHECK(std::stod(r[rec.col("cost")]) == Approx(cost(*best).first * 25));  // 5 x 5 particles
  }
  REQUIRE(report.recommendations.size() == 2);
  CHECK(report.recommendations[1].scope == "overall");
  CHECK(report.recommendations[1].found);
  CHECK(accuracy_summary(report).find("cheapest configuration") != std::string::npos);

  // a tolerance nothing meets is said so, in the file and the summary
  TempDir dir2("recommend-none");
  o.out_dir = dir2.str();
  o.tolerance = 1e-30;
  o.integrators = {cloth::Integrator::explicit_euler};
  const AccuracyReport none = run_accuracy(sc, o);
  REQUIRE(none.recommendations.size() == 2);
  CHECK_FALSE(none.recommendations[0].found);
  CHECK_FALSE(none.recommendations[1].found);
  const Csv rec2 = read_csv(dir2.path / "recommendation.csv");
  REQUIRE(rec2.rows.size() == 2);
  CHECK(rec2.rows[1][rec2.col("integrator")].empty());
  CHECK(accuracy_summary(none).find("nothing meets the tolerance") != std::string::npos);
}

TEST_CASE("accuracy sweep: the result does not depend on the number of jobs", "[sweep]") {
  TempDir one("jobs1"), two("jobs2");
  const Scenario sc = parse_scenario(kSwing, "swing.toml");
  AccuracyOptions o = quick_options(one.str());
  o.tolerance = 1e-4;  // m
  o.jobs = 1;
  run_accuracy(sc, o);
  o.out_dir = two.str();
  o.jobs = 2;
  run_accuracy(sc, o);
  CHECK(without_wall_time(read_csv(one.path / "work_precision.csv")) ==
        without_wall_time(read_csv(two.path / "work_precision.csv")));
  CHECK(read_csv(one.path / "convergence.csv").rows == read_csv(two.path / "convergence.csv").rows);
  // the recommendation is counted, not timed: the same row whatever ran beside it
  const auto chosen = [](const Csv& rec) {
    std::vector<std::vector<std::string>> out;
    for (auto row : rec.rows) {
      row.erase(row.begin() + static_cast<std::ptrdiff_t>(rec.col("wall_s_per_sim_s")));
      out.push_back(row);
    }
    return out;
  };
  CHECK(chosen(read_csv(one.path / "recommendation.csv")) ==
        chosen(read_csv(two.path / "recommendation.csv")));
}

TEST_CASE("accuracy sweep: identical engines run once", "[sweep]") {
  TempDir dir("twins");
  // a second engine that differs in name only
  const std::string text = std::string(kSwing) + "[[engine]]\nname = \"twin\"\ndt = 4e-3\n";
  const Scenario sc = parse_scenario(text, "twins.toml");
  AccuracyOptions o = quick_options(dir.str());
  o.integrators = {cloth::Integrator::midpoint, cloth::Integrator::rk4};
  const AccuracyReport report = run_accuracy(sc, o);
  REQUIRE(report.rows.size() == 16);
  CHECK(report.runs == 8);
  for (size_t i = 0; i < 8; ++i) {
    const AccuracyRow &a = report.rows[i], &b = report.rows[i + 8];
    CHECK(a.engine == "custom");
    CHECK(b.engine == "twin");
    CHECK(a.integrator == b.integrator);
    CHECK(a.dt == b.dt);
    CHECK(a.error_max == b.error_max);
    CHECK(b.rerun.find("engine.twin.") != std::string::npos);
  }
}

namespace {

/// kSwing with `overrides`, then 200 times stiffer and 1000 times lighter, with implicit Euler
/// at 1/50 s as its only engine: its steps are far past what rk4 can take
Scenario stiff_implicit(std::vector<std::string> overrides) {
  for (const char* o : {"cloth.stiffness={ structural = 4000.0, shear = 4000.0, bend = 4000.0 }",
                        "cloth.total_mass=2.5e-3", "engine.custom.integrator=\"implicit-euler\"",
                        "engine.custom.dt=0.02"})
    overrides.push_back(o);
  return parse_scenario(kSwing, "swing.toml", overrides);
}

double rk4_limit(const Scenario& sc) {
  return cloth::predicted_stable_dt(cloth::Integrator::rk4,
                                    cloth::linear_spectrum(cloth::build_model(sc.scene)));
}

/// A reference within a quarter of rk4's predicted limit, dividing a frame, saying so.
void check_rk4_can_take(const AccuracyReference& ref, double limit, double frame_interval) {
  INFO(ref.description);
  CHECK(ref.dt <= 0.25 * limit);
  const double steps = frame_interval / ref.dt;
  CHECK(steps == Approx(std::round(steps)).epsilon(1e-9));
  CHECK(ref.description.find("rk4's predicted limit") != std::string::npos);
}

}  // namespace

TEST_CASE("accuracy sweep: implicit Euler at large steps gets a reference rk4 can take",
          "[sweep]") {
  // the swing with implicit Euler at 1/50 s: a quarter of the smallest swept step is more
  // than ten times rk4's limit, and a reference taken there blows up in its first steps
  TempDir dir("implicit");
  const Scenario sc = stiff_implicit({});
  AccuracyOptions o = quick_options(dir.str());
  o.halvings = 2;
  o.integrators = {cloth::Integrator::implicit_euler};
  REQUIRE(0.01 / 4 > 10 * rk4_limit(sc));
  const AccuracyReport report = run_accuracy(sc, o);
  check_rk4_can_take(report.reference, rk4_limit(sc), sc.frame_interval);
  // the reference is good enough to measure implicit Euler's first-order error against
  REQUIRE(report.rows.size() == 2);
  for (const AccuracyRow& r : report.rows) {
    CHECK(r.stable);
    CHECK(std::isfinite(r.error_max));
    CHECK(r.error_max > 100 * report.reference.error_floor);
  }
}

TEST_CASE("accuracy sweep: the resolution study at large steps gets a reference rk4 can take",
          "[sweep]") {
  // the flap so, on 3 x 3 and 5 x 5 grids: the smallest step run is far past what rk4 can
  // take on the finest grid (the study stopped, telling the user to sweep smaller steps)
  TempDir dir("implicit-grids");
  const Scenario sc = stiff_implicit(kFlap);
  AccuracyOptions o = quick_options(dir.str());
  o.halvings = 1;
  o.integrators = {cloth::Integrator::implicit_euler};
  o.resolutions = {3, 5};
  REQUIRE(sc.scene.cloth.nu == 5);
  REQUIRE(0.02 > 10 * rk4_limit(sc));
  const AccuracyReport report = run_accuracy(sc, o);
  CHECK(report.resolution_reference.nu == 5);
  check_rk4_can_take(report.resolution_reference, rk4_limit(sc), sc.frame_interval);
  // measured against it, every row's error is finite: on the finest grid it is implicit
  // Euler's time-step error alone
  REQUIRE(report.resolution_rows.size() == 2);
  for (const AccuracyRow& r : report.resolution_rows) {
    INFO(r.particles << " particles: error_final " << r.error_final);
    CHECK(r.stable);
    CHECK(std::isfinite(r.error_final));
    CHECK(r.error_final > 0);
  }
}

TEST_CASE("accuracy plan: a shard of a resolution study is refused by the plan", "[sweep]") {
  // refused while planning, before the references' spectra are computed (under the sanitisers
  // seconds on a flag) and before any folder is made
  TempDir dir("shard-grids");
  const Scenario sc = stiff_implicit(kFlap);
  AccuracyOptions o = quick_options(dir.str());
  o.resolutions = {3, 5};
  o.shard = parse_shard("1/2");
  CHECK_THROWS_WITH(plan_accuracy(sc, o), Catch::Contains("--shard 1/2 with --resolutions"));
  o.resolutions = {};
  CHECK(!plan_accuracy(sc, o).configs.empty());
}

TEST_CASE("accuracy plan: a chosen reference step is taken as given or refused with its reason",
          "[sweep]") {
  TempDir dir("reference-dt");
  const Scenario sc = stiff_implicit({});
  AccuracyOptions o = quick_options(dir.str());
  o.halvings = 2;  // swept: 0.02 s and 0.01 s
  o.integrators = {cloth::Integrator::implicit_euler};
  const double quarter = 0.25 * rk4_limit(sc);
  const double automatic = plan_accuracy(sc, o).reference.dt;
  // half the automatic step: within the quarter limit, dividing a frame, finer than 0.01 s
  o.reference_dt = automatic / 2;
  const AccuracyPlan plan = plan_accuracy(sc, o);
  CHECK(plan.reference.dt == automatic / 2);
  CHECK(plan.floor_run.spec.dt == automatic);
  CHECK_THAT(plan.reference.description, Catch::Contains("(--reference-dt)"));
  // past the quarter limit: rk4 there is no reference
  const double steps = std::floor(sc.frame_interval / quarter);
  REQUIRE(steps >= 1);
  o.reference_dt = sc.frame_interval / steps;
  REQUIRE(o.reference_dt > quarter);
  CHECK_THROWS_WITH(plan_accuracy(sc, o), Catch::Contains("past a quarter of rk4's predicted"));
  // coarser than the steps it judges
  o.reference_dt = 0.02;
  CHECK_THROWS_WITH(plan_accuracy(sc, o), Catch::Contains("at least as fine as the steps"));
  // not a whole number of steps a frame: the message offers one that is
  o.reference_dt = automatic * 0.7;
  const double per_frame = sc.frame_interval / o.reference_dt;
  REQUIRE(std::abs(per_frame - std::round(per_frame)) > 1e-3);
  CHECK_THROWS_WITH(plan_accuracy(sc, o),
                    Catch::Contains("does not divide frame_interval") && Catch::Contains("e.g."));
}

TEST_CASE("accuracy sweep: resume runs only the missing rows", "[sweep]") {
  TempDir dir("resume");
  const Scenario sc = parse_scenario(kSwing, "swing.toml");
  AccuracyOptions o = quick_options(dir.str());
  const AccuracyReport first = run_accuracy(sc, o);
  CHECK(first.runs == static_cast<int>(first.rows.size()));
  const fs::path wp = dir.path / "work_precision.csv";
  const Csv full = read_csv(wp);

  // an interrupted sweep: rows 3, 10 and 17 missing and a last line cut short
  {
    std::ifstream in(wp);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    in.close();
    std::ofstream out(wp);
    for (size_t i = 0; i < lines.size(); ++i)
      if (i != 1 + 3 && i != 1 + 10 && i != 1 + 17) out << lines[i] << "\n";
    out << "custom,rk4,0.0";
  }
  o.resume = true;
  const AccuracyReport resumed = run_accuracy(sc, o);
  CHECK(resumed.runs == 3);
  CHECK(resumed.resumed == static_cast<int>(first.rows.size()) - 3);
  CHECK(without_wall_time(read_csv(wp)) == without_wall_time(full));
  REQUIRE(resumed.convergence.size() == first.convergence.size());
  for (size_t i = 0; i < first.convergence.size(); ++i)
    CHECK(resumed.convergence[i].order == first.convergence[i].order);

  // nothing left to do: no run at all, not even the reference
  const AccuracyReport again = run_accuracy(sc, o);
  CHECK(again.runs == 0);
  CHECK(again.reference.error_floor == first.reference.error_floor);

  // another scene in the same folder is not resumed
  const Scenario other = parse_scenario(kSwing, "swing.toml", {"cloth.damping=0.4"});
  CHECK_THROWS_WITH(run_accuracy(other, o), Catch::Contains("cannot resume"));
  // nor another reference
  AccuracyOptions finer = o;
  finer.halvings = 5;
  CHECK_THROWS_WITH(run_accuracy(sc, finer), Catch::Contains("cannot resume"));
}

TEST_CASE("accuracy sweep: the resolution error falls toward the finest grid", "[sweep]") {
  TempDir dir("resolution");
  const Scenario sc = parse_scenario(kSwing, "swing.toml", kFlap);
  AccuracyOptions o = quick_options(dir.str());
  o.integrators = {cloth::Integrator::rk4};
  o.halvings = 2;
  o.resolutions = {9, 3, 17, 5};
  o.tolerance = 0.05;  // m
  const AccuracyReport report = run_accuracy(sc, o);
  REQUIRE(report.resolution_rows.size() == 4);
  CHECK(report.resolution_reference.nu == 17);
  CHECK(report.resolution_reference.dt == Approx(5e-4).epsilon(1e-12));
  const std::vector<int> particles = {9, 25, 81, 289};
  for (size_t i = 0; i < 4; ++i) {
    const AccuracyRow& r = report.resolution_rows[i];
    INFO(r.particles << " particles: error_final " << r.error_final);
    CHECK(r.particles == particles[i]);
    CHECK(r.stable);
    if (i > 0) CHECK(r.error_final < report.resolution_rows[i - 1].error_final);
  }
  // the finest grid differs from the reference by its time step alone
  CHECK(report.resolution_rows[3].error_final < 1e-3 * report.resolution_rows[2].error_final);

  const Csv csv = read_csv(dir.path / "resolution.csv");
  CHECK(csv.header == std::vector<std::string>{"engine", "integrator", "particles", "dt", "stable",
                                               "error_final", "wall_s_per_sim_s", "force_evals",
                                               "cg_iterations", "rerun"});
  REQUIRE(csv.rows.size() == 4);
  CHECK(csv.rows[0][csv.col("rerun")] ==
        "--set cloth.particles=[3,3] --set cloth.total_mass=2.5 --set "
        "engine.custom.integrator=rk4 --set engine.custom.dt=0.001");
  // the cheapest grid within 5 cm, found from the file alone: force evaluations (and CG
  // iterations) times particles, the work of a step growing with the grid
  const Csv rec = read_csv(dir.path / "resolution_recommendation.csv");
  REQUIRE(rec.rows.size() == 2);
  const std::vector<std::string>* best = nullptr;
  const auto work = [&](const std::vector<std::string>& r) {
    return (double(std::stoll(r[csv.col("force_evals")])) +
            kCgIterationCost * double(std::stoll(r[csv.col("cg_iterations")]))) *
           std::stod(r[csv.col("particles")]);
  };
  for (const auto& r : csv.rows) {
    if (r[csv.col("stable")] != "1" || std::stod(r[csv.col("error_final")]) > o.tolerance) continue;
    if (!best || work(r) < work(*best)) best = &r;
  }
  REQUIRE(best);
  CHECK(rec.rows[1][rec.col("particles")] == (*best)[csv.col("particles")]);

  // resumed with the 5 x 5 row gone, only that row runs again
  {
    std::ifstream in(dir.path / "resolution.csv");
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    in.close();
    std::ofstream out(dir.path / "resolution.csv");
    for (size_t i = 0; i < lines.size(); ++i)
      if (i != 2) out << lines[i] << "\n";
  }
  o.resume = true;
  const AccuracyReport resumed = run_accuracy(sc, o);
  CHECK(resumed.runs == 1);
  const Csv again = read_csv(dir.path / "resolution.csv");
  REQUIRE(again.rows.size() == csv.rows.size());
  for (size_t i = 0; i < csv.rows.size(); ++i) {
    CHECK(again.rows[i][again.col("error_final")] == csv.rows[i][csv.col("error_final")]);
    CHECK(again.rows[i][again.col("rerun")] == csv.rows[i][csv.col("rerun")]);
  }
  CHECK(resumed.resolution_rows[0].rerun.find("--set cloth.particles=[3,3]") == 0);
}

TEST_CASE("material distance: bilinear interpolation is exact for an affine shape", "[sweep]") {
  // the same sheared, stretched sheet sampled on 3 x 4 and 7 x 5 grids
  const auto sheet = [](int nu, int nv) {
    cloth::Matrix3X x(3, nu * nv);
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const double u = double(i) / (nu - 1), v = double(j) / (nv - 1);
        x.col(j * nu + i) = cloth::Vector3(2 * u + 0.5 * v, 1 - v, 0.3 * u);
      }
    return x;
  };
  CHECK(material_rms_distance(sheet(3, 4), 3, 4, sheet(7, 5), 7, 5) == Approx(0).margin(1e-14));
  // a rigid shift by d is a distance d everywhere
  cloth::Matrix3X moved = sheet(7, 5);
  moved.row(1).array() += 0.25;
  CHECK(material_rms_distance(sheet(3, 4), 3, 4, moved, 7, 5) == Approx(0.25));
  CHECK(fitted_order({1e-3, 5e-4}, {4e-6, 1e-6}) == Approx(2));
  CHECK(std::isnan(fitted_order({1e-3}, {1e-6})));
}

TEST_CASE("accuracy sweep: options a user can get wrong", "[sweep]") {
  TempDir dir("errors");
  const Scenario sc = parse_scenario(kSwing, "swing.toml");
  AccuracyOptions o = quick_options(dir.str());
  o.dts = {3e-3};  // 0.02 s frames are not a whole number of 3 ms steps
  CHECK_THROWS_AS(run_accuracy(sc, o), clothbench::UserError);
  CHECK_THROWS_WITH(run_accuracy(sc, o), Catch::Contains("does not divide frame_interval"));
  o.dts = {};
  o.resolutions = {3, 5};  // the two corners are given by indices
  CHECK_THROWS_WITH(run_accuracy(sc, o), Catch::Contains("indices"));
  o.resolutions = {};
  o.engines = {"bullet"};
  CHECK_THROWS_WITH(run_accuracy(sc, o), Catch::Contains("no such engine"));
  // an unknown integrator name is refused where it is parsed (--integrator, cli.integrator_names)
}

TEST_CASE("recommendations: a NaN error, cost or tolerance never passes", "[sweep]") {
  const double nan = std::nan("");
  const auto row = [](const std::string& engine, const std::string& integrator, double error,
                      double wall) {
    AccuracyRow r;
    r.engine = engine;
    r.integrator = integrator;
    r.particles = 4;
    r.dt = 1e-3;
    r.stable = true;
    r.error_max = r.error_final = error;
    r.force_evals = 100;
    r.wall_s_per_sim_s = wall;
    return r;
  };
  // a stable row with a NaN error is not within any tolerance
  std::vector<AccuracyRow> rows = {row("custom", "rk4", nan, 1.0)};
  std::vector<Recommendation> rec = recommend_all(rows, {"custom"}, 1.0, &AccuracyRow::error_max);
  CHECK_FALSE(rec[0].found);
  CHECK_FALSE(rec[1].found);
  // nothing is within a NaN tolerance
  rows = {row("custom", "rk4", 1e-6, 1.0)};
  rec = recommend_all(rows, {"custom"}, nan, &AccuracyRow::error_max);
  CHECK_FALSE(rec[0].found);
  // a Bullet row whose wall time is NaN does not win overall because it comes first
  rows = {row("bullet", "", 1e-6, nan), row("custom", "rk4", 1e-6, 5.0)};
  rec = recommend_all(rows, {"bullet", "custom"}, 1e-3, &AccuracyRow::error_max);
  REQUIRE(rec.size() == 3);
  CHECK(rec[2].found);
  CHECK(rec[2].engine == "custom");
}

TEST_CASE("a sweep's variant of an engine is labelled with what it runs", "[accuracy]") {
  // the reference of an accuracy sweep is rk4 made from the scenario's engine: its progress
  // lines must not call it by that engine's name alone
  EngineSpec e;
  e.name = "custom-implicit-euler-30";
  e.solver.integrator = cloth::Integrator::implicit_euler;
  e.dt = 1.0 / 30;
  const EngineSpec reference = with_integrator_and_dt(e, cloth::Integrator::rk4, 8.13e-5);
  CHECK(reference.name == e.name);  // rerun commands name the scenario's engine
  CHECK(reference.label == "custom-implicit-euler-30 (rk4, dt = 8.13e-05 s)");
  CHECK(with_integrator_and_dt(e, cloth::Integrator::implicit_euler, 0.01).label ==
        "custom-implicit-euler-30 (dt = 0.01 s)");
  CHECK(with_integrator_and_dt(e, std::nullopt, 0.01).label ==
        "custom-implicit-euler-30 (dt = 0.01 s)");
}
