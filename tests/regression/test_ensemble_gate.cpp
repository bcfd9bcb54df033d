#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cloth/model/model.hpp"
#include "cloth/model/triangle_mesh.hpp"
#include "harness/gate/ensemble_gate.hpp"
#include "harness/gate/ensemble_runs.hpp"
#include "harness/gate/ensemble_size.hpp"
#include "harness/gate/regression_check.hpp"
#include "harness/gate/tolerances_file.hpp"
#include "harness/gate/welch_test.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/ensemble_member.hpp"
#include "tolerances.hpp"

using namespace clothbench;
namespace fs = std::filesystem;

namespace {

// closed forms of Student's two-sided tail P(|T| >= t), from the densities' integrals
double tail_dof1(double t) {  // Cauchy
  return 1.0 - 2.0 * std::atan(std::abs(t)) / M_PI;
}
double tail_dof2(double t) {
  return 1.0 - std::abs(t) / std::sqrt(2.0 + t * t);
}
double tail_dof3(double t) {
  const double x = std::abs(t);
  return 1.0 -
         2.0 / M_PI * (x / (std::sqrt(3.0) * (1.0 + x * x / 3.0)) + std::atan(x / std::sqrt(3.0)));
}
double tail_dof4(double t) {
  const double x = std::abs(t), q = 1.0 + x * x / 4.0;
  return 1.0 - 0.75 * x / std::sqrt(q) * (1.0 - x * x / (12.0 * q));
}

}  // namespace

TEST_CASE("the t distribution's tail equals its closed forms and is symmetric", "[ensemble]") {
  const double t = GENERATE(0.0, 0.3, 1.0, 1.7, 3.5, 12.0, 150.0);
  CHECK(student_t_two_sided(t, 1) == Approx(tail_dof1(t)).epsilon(tol::kStudentTail).margin(1e-15));
  CHECK(student_t_two_sided(t, 2) == Approx(tail_dof2(t)).epsilon(tol::kStudentTail).margin(1e-15));
  CHECK(student_t_two_sided(t, 3) == Approx(tail_dof3(t)).epsilon(tol::kStudentTail).margin(1e-15));
  CHECK(student_t_two_sided(t, 4) == Approx(tail_dof4(t)).epsilon(tol::kStudentTail).margin(1e-15));
  // symmetric in t, 1 at t = 0, falling with |t|, rising with the degrees of freedom's tails
  CHECK(student_t_two_sided(-t, 7.5) == student_t_two_sided(t, 7.5));
  CHECK(student_t_two_sided(0.0, 7.5) == 1.0);
  CHECK(student_t_two_sided(t + 0.1, 7.5) < student_t_two_sided(t, 7.5) + 1e-300);
  // the incomplete beta's exact cases: I_x(a, 1) = x^a and I_x(a, b) = 1 - I_(1-x)(b, a)
  const double x = GENERATE(0.05, 0.5, 0.93);
  CHECK(regularized_incomplete_beta(2.5, 1.0, x) == Approx(std::pow(x, 2.5)).epsilon(1e-13));
  CHECK(regularized_incomplete_beta(3.0, 0.5, x) ==
        Approx(1.0 - regularized_incomplete_beta(0.5, 3.0, 1.0 - x)).epsilon(1e-13));
}

TEST_CASE("Welch's test of a hand-made pair of samples", "[ensemble]") {
  // means 2 and 5, variances 1 and 1: t = 3 / sqrt(2/3), Welch's dof (2/3)^2 / (2 (1/3)^2 / 2) = 4
  const WelchResult w = welch_test({1, 2, 3}, {4, 5, 6});
  CHECK(w.mean_a == 2.0);
  CHECK(w.mean_b == 5.0);
  CHECK(w.sd_a == Approx(1.0));
  CHECK(w.t == Approx(3.0 / std::sqrt(2.0 / 3.0)));
  CHECK(w.dof == Approx(4.0));
  CHECK(w.p == Approx(tail_dof4(w.t)).epsilon(tol::kStudentTail));
  // no spread: equal means pass with p = 1, different ones fail with p = 0
  CHECK(welch_test({1, 1}, {1, 1, 1}).p == 1.0);
  CHECK(welch_test({1, 1}, {2, 2}).p == 0.0);
  // too few or not finite values: no verdict
  CHECK(std::isnan(welch_test({1}, {1, 2}).p));
  CHECK(std::isnan(welch_test({1, NAN}, {1, 2}).p));
}

TEST_CASE("an ensemble gate fails a mean moved by 10 sigma and passes an unchanged one",
          "[ensemble]") {
  // two draws of 8 from one distribution (mean 0, sd about 1), written out by hand
  const std::vector<double> base = {0.31, -1.22, 0.87, -0.45, 1.64, -0.09, -0.73, 0.52};
  const std::vector<double> again = {-0.58, 0.96, 0.12, -1.41, 0.44, 1.07, -0.26, -0.35};
  std::vector<double> moved = again;
  for (double& v : moved) v += 10.0;
  const double alpha = kEnsembleFalseAlarm / 4;
  const Gate same = ensemble_gate("s", "e", "q", base, base, alpha);
  CHECK(same.pass);
  CHECK(same.note.find("p = 1") != std::string::npos);
  CHECK(ensemble_gate("s", "e", "q", base, again, alpha).pass);
  const Gate g = ensemble_gate("s", "e", "q", base, moved, alpha);
  CHECK_FALSE(g.pass);
  CHECK(g.note.find("t = ") != std::string::npos);
  CHECK(g.difference == Approx(10.0 + (0.0 - 0.0)).margin(0.5));
  // one member is no ensemble
  CHECK_FALSE(ensemble_gate("s", "e", "q", {1.0}, base, alpha).pass);
}

TEST_CASE("the growth exponent of two hand-made runs", "[ensemble]") {
  cloth::Matrix3X a = cloth::Matrix3X::Zero(3, 4), b = a, c = a, d = a;
  b(1, 2) = 1e-13;  // start 1e-13 m apart
  d(0, 1) = 1e-3;   // end 1e-3 m apart, 10 s later
  CHECK(growth_exponent(a, b, c, d, 10.0) == Approx(std::log(1e10) / 10.0));
  CHECK(std::isinf(growth_exponent(a, a, c, d, 10.0)));
  CHECK(std::isnan(growth_exponent(a, b, c, c, 10.0)));
}

TEST_CASE("ensemble members are perturbed deterministically at round-off size", "[ensemble]") {
  cloth::Scene grid;  // the default 25 x 25 grid, 4 m wide
  const cloth::Model base = cloth::build_model(grid);
  // member 0 is the scene itself, bit for bit
  CHECK((cloth::build_model(perturbed_scene(grid, 0)).x0.array() == base.x0.array()).all());
  const int member = GENERATE(1, 2, 7);
  const cloth::Scene s = perturbed_scene(grid, member);
  const cloth::Model m = cloth::build_model(s);
  // the same member twice: the same bits; another seed or member: another offset
  CHECK((cloth::build_model(perturbed_scene(grid, member)).x0.array() == m.x0.array()).all());
  CHECK(perturbed_scene(grid, member, 1).cloth.center != s.cloth.center);
  CHECK(perturbed_scene(grid, member + 1).cloth.center != s.cloth.center);
  // every particle moves by one offset of at most 1e-13 of the extent per axis, above zero
  const cloth::Vector3 offset = s.cloth.center - grid.cloth.center;
  CHECK(offset.cwiseAbs().maxCoeff() <= kRoundOffPerturbation * 4.0);
  CHECK(offset.norm() > 1e-3 * kRoundOffPerturbation * 4.0);
  for (Eigen::Index p = 0; p < m.x0.cols(); ++p)
    CHECK((m.x0.col(p) - base.x0.col(p) - offset).norm() < 1e-15);
  // rest lengths are the scene's to round-off: the perturbation moves, it does not deform
  const auto before = base.springs.links(), after = m.springs.links();
  REQUIRE(after.size() == before.size());
  for (size_t k = 0; k < after.size(); ++k)
    REQUIRE(after[k].rest == Approx(before[k].rest).epsilon(1e-14));
  // a mesh moves as a whole too
  auto mesh = std::make_shared<cloth::TriangleMesh>();
  mesh->x = cloth::Matrix3X::Zero(3, 3);
  mesh->x(0, 1) = 1.0, mesh->x(2, 2) = 1.0;
  mesh->triangles = {{0, 1, 2}};
  cloth::Scene ms;
  ms.mesh = mesh;
  const cloth::Matrix3X moved = perturbed_scene(ms, member).mesh->x;
  const cloth::Vector3 d = moved.col(0) - mesh->x.col(0);
  CHECK(d.norm() > 0);
  CHECK(d.cwiseAbs().maxCoeff() <= kRoundOffPerturbation * std::sqrt(2.0));
  CHECK((moved.col(1) - mesh->x.col(1) - d).norm() < 1e-16);
  CHECK(ms.mesh->x(0, 1) == 1.0);  // the scene's own mesh is left alone
}

namespace {

// every quantity's tolerance, then extra (the tables under test)
std::string tolerance_text(const std::string& extra) {
  std::string t;
  for (const std::string& q : kMetricQuantities) t += q + " = { abs = 0 }\n";
  return t + "final_shape_rms = { abs = 1e-6 }\n" + extra;
}

// the message of read_tolerances' refusal of text ("" when it reads it)
std::string refusal(const std::string& text) {
  const ScratchFolder dir("clothbench-test-ensemble-");
  const fs::path p = fs::path(dir.path()) / "tolerances.toml";
  std::ofstream(p) << text;
  try {
    read_tolerances(p);
  } catch (const UserError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a tolerance file's ensembles: N >= 2 whole members, known quantities", "[ensemble]") {
  const std::string table = "[ensemble.bullet]\nreason = \"contacts flip\"\n";
  const std::string good = table + "members = 8\nquantities = [\"final_com_y\"]\n";
  {
    const ScratchFolder dir("clothbench-test-ensemble-");
    const fs::path p = fs::path(dir.path()) / "tolerances.toml";
    std::ofstream(p) << tolerance_text(good);
    const Tolerances t = read_tolerances(p);
    REQUIRE(t.ensemble.count("bullet"));
    CHECK(t.ensemble.at("bullet").members == 8);
    CHECK(t.ensemble.at("bullet").quantities == std::set<std::string>{"final_com_y"});
  }
  {
    // a [test] metric, named test.<metric>, is a quantity an ensemble may gate
    const ScratchFolder dir("clothbench-test-ensemble-");
    const fs::path p = fs::path(dir.path()) / "tolerances.toml";
    std::ofstream(p) << tolerance_text(table + "members = 8\nquantities = [\"test.folds\"]\n");
    CHECK(read_tolerances(p).ensemble.at("bullet").quantities ==
          std::set<std::string>{"test.folds"});
  }
  // one member, a fraction, a string, none: refused on the members line (line 10 or 11)
  const std::string quantities = "quantities = [\"final_com_y\"]\n";
  for (const char* bad : {"members = 1\n", "members = 2.5\n", "members = \"eight\"\n",
                          "members = 0\n", "members = -3\n"}) {
    const std::string msg = refusal(tolerance_text(table + bad + quantities));
    CHECK_THAT(msg, Catch::Contains("tolerances.toml:13: ensemble.bullet.members"));
    CHECK_THAT(msg, Catch::Contains("from 2 to 1000"));
  }
  CHECK_THAT(refusal(tolerance_text(table + quantities)), Catch::Contains("no members"));
  // a top-level number, an unknown key or quantity, a quantity also ungated: refused
  CHECK_THAT(refusal(tolerance_text("ensemble = 8\n")),
             Catch::Contains("tolerances.toml:11: ensemble: expected tables [ensemble.<engine>]"));
  CHECK_THAT(refusal(tolerance_text(good + "size = 3\n")), Catch::Contains("unknown key"));
  CHECK_THAT(refusal(tolerance_text(table + "members = 8\nquantities = [\"colour\"]\n")),
             Catch::Contains("unknown quantity \"colour\""));
  CHECK_THAT(refusal(tolerance_text(table + "members = 8\nquantities = []\n")),
             Catch::Contains("no quantities"));
  CHECK_THAT(refusal(tolerance_text("[ungated.bullet]\nquantities = [\"final_com_y\"]\n"
                                    "reason = \"r\"\n" +
                                    good)),
             Catch::Contains("also in [ungated.bullet]"));
}

namespace {

// a chain of 6 particles hanging for 0.2 s, under two custom engines: checks in milliseconds
const char* kChain =
    "name = \"ensemble_chain\"\n"
    "duration = 0.2\nframe_interval = 0.01\nsnapshot_interval = 0.1\n"
    "blowup_strain = 1.0\nreference = \"custom-rk4\"\ngravity = [0.0, -9.8, 0.0]\n"
    "[cloth]\nparticles = [1, 6]\nsize = [0.0, 0.5]\ncenter = [0.0, 1.0, 0.0]\n"
    "plane = \"xy\"\nparticle_mass = 0.1\nstiffness = { structural = 200.0 }\n"
    "damping = 1.0\nair_drag = 0.0\n"
    "[[constraint]]\nselect = \"indices\"\nhold = \"xyz\"\nlist = [[0, 0]]\n"
    "[[engine]]\nname = \"custom-rk4\"\nkind = \"custom\"\nintegrator = \"rk4\"\ndt = 1e-4\n"
    "[[engine]]\nname = \"custom-symplectic-euler\"\nkind = \"custom\"\n"
    "integrator = \"symplectic-euler\"\ndt = 1e-4\n";

// the gates of one engine's quantity
std::vector<Gate> gates_of(const std::vector<Gate>& gates, const std::string& engine,
                           const std::string& quantity) {
  std::vector<Gate> out;
  for (const Gate& g : gates)
    if (g.engine == engine && g.quantity == quantity) out.push_back(g);
  return out;
}

}  // namespace

namespace {

// kChain in a scratch folder with a baseline folder whose tolerances end in `ensemble`, and
// the check options that use it
struct ChainBaseline {
  ScratchFolder dir{"clothbench-test-ensemble-"};
  fs::path base = fs::path(dir.path()) / "baselines" / "ensemble_chain";
  std::string scenario = (fs::path(dir.path()) / "chain.toml").string();
  CheckOptions options;
  explicit ChainBaseline(const std::string& ensemble) {
    fs::create_directories(base);
    std::ofstream(scenario) << kChain;
    std::ofstream(base / "tolerances.toml") << tolerance_text(ensemble);
    options.baseline_dir = base.parent_path().string();
    options.progress = false;
    options.jobs = 2;
  }
};

}  // namespace

TEST_CASE("check records an ensemble, gates it, and catches a damping change", "[ensemble]") {
  const ChainBaseline chain(
      "[ensemble.custom-symplectic-euler]\nmembers = 4\nreason = \"test\"\n"
      "quantities = [\"final_com_y\", \"final_shape_rms\"]\n");
  const fs::path& base = chain.base;
  const std::string& scenario = chain.scenario;
  CheckOptions o = chain.options;
  CheckOptions update = o;
  update.update = true;
  check_scenario(scenario, update);
  // the members' values, member 0 first, and the growth exponent
  const EnsembleValues recorded = read_ensemble((base / "metrics_ensemble.csv").string());
  REQUIRE(recorded.at("custom-symplectic-euler/final_com_y").size() == 4);
  CHECK(recorded.at("custom-symplectic-euler/final_shape_rms")[0] == 0.0);
  CHECK(recorded.at("custom-symplectic-euler/growth_exponent").size() == 1);
  CHECK(recorded.count("custom-rk4/final_com_y") == 0);
  // without its ensemble (CheckOptions::ensemble false, the command line's --no-ensemble) its
  // rows are shown, not gated
  const auto plain =
      gates_of(check_scenario(scenario, o), "custom-symplectic-euler", "final_com_y");
  REQUIRE(plain.size() == 1);
  CHECK_FALSE(plain[0].gated);
  // with it, the same members reproduce their record
  o.ensemble = true;
  const std::vector<Gate> gates = check_scenario(scenario, o);
  for (const Gate& g : gates) CHECK(g.pass);
  const auto row = gates_of(gates, "custom-symplectic-euler", "final_com_y");
  REQUIRE(row.size() == 1);
  CHECK(row[0].gated);
  CHECK_THAT(row[0].note, Catch::Contains("p = 1"));
  // half the damping moves the ensemble's mean far outside its round-off spread
  o.overrides = {"cloth.damping=0.5"};
  const auto moved =
      gates_of(check_scenario(scenario, o), "custom-symplectic-euler", "final_com_y");
  REQUIRE(moved.size() == 1);
  CHECK_FALSE(moved[0].pass);
}

// The ensemble's size: Welch's power against Monte Carlo, the shift an ensemble catches, the
// members a goal needs, the tolerance file's `detect`, and check --update choosing N.

TEST_CASE("Welch's power by quadrature equals its Monte Carlo rate", "[ensemble]") {
  // Independent route: the rejection rate of scipy.stats.ttest_ind(equal_var=False) on
  // normal samples of sd 1, numpy default_rng seeds 1 and 2, 200,000 or 400,000 pairs (so one
  // binomial standard deviation is at most 0.001); the bound is four of them.
  struct Case {
    double shift;
    int n;
    double alpha, rate, trials;
  };
  for (const Case c :
       {Case{3.260934827, 8, 2.5e-4, 0.864905, 2e5}, Case{5.848132131, 4, 1e-3, 0.71973, 2e5},
        Case{2.001009921, 16, 2e-4, 0.894645, 2e5},
        Case{0.0, 8, 0.05, 0.04804, 4e5},  // Welch is a little conservative
        Case{0.0, 2, 0.05, 0.02356, 4e5},  // and much more so at n = 2
        Case{3.39347, 8, 2.5e-4, 0.90058, 4e5}, Case{545.798, 2, 1e-3, 0.8995275, 4e5}}) {
    INFO("shift " << c.shift << ", n " << c.n << ", alpha " << c.alpha);
    const double sigma = std::sqrt(c.rate * (1 - c.rate) / c.trials);
    CHECK(std::abs(welch_power(c.shift, c.n, c.alpha) - c.rate) < 4 * sigma);
  }
  // the textbook pooled-t sizing would claim 0.9 at n = 4, alpha = 1e-3 for this shift
  CHECK(welch_power(5.848132131, 4, 1e-3) < 0.75);
}

TEST_CASE("the shift an ensemble catches: in the spread's unit, falling with N", "[ensemble]") {
  const double a = 2.5e-4;
  const double d8 = detectable_shift(1.0, 8, a);
  CHECK(welch_power(d8, 8, a) == Approx(kEnsemblePower).margin(1e-6));
  CHECK(detectable_shift(0.003, 8, a) == Approx(0.003 * d8).epsilon(1e-6));
  CHECK(detectable_shift(1.0, 16, a) < d8);
  CHECK(detectable_shift(1.0, 4, a) > d8);
  CHECK(detectable_shift(0.0, 8, a) == 0.0);
  CHECK(std::isnan(detectable_shift(1.0, 1, a)));
  CHECK(std::isnan(detectable_shift(NAN, 8, a)));
  // members_needed is the smallest N whose detectable shift reaches the goal
  for (const double goal : {3.0, 1.0, 0.5}) {
    const int n = members_needed(1.0, goal, a, 4, 1000);
    INFO("goal " << goal << " spreads: " << n << " members");
    REQUIRE(n > 4);
    CHECK(detectable_shift(1.0, n, a) <= goal);
    CHECK(detectable_shift(1.0, n - 1, a) > goal);
  }
  CHECK(members_needed(1.0, 100.0, a, 4, 1000) == 4);  // the fewest asked for
  CHECK(members_needed(1.0, 0.01, a, 4, 1000) == 0);   // not within 1000
  CHECK(members_needed(0.0, 1e-9, a, 4, 1000) == 4);
}

TEST_CASE("a tolerance file's detect: a shift > 0 for each quantity, or members, not both",
          "[ensemble]") {
  const std::string table =
      "[ensemble.bullet]\nreason = \"contacts flip\"\n"
      "quantities = [\"final_com_y\", \"final_shape_rms\"]\n";
  const std::string detect = "detect = { final_com_y = 0.001, final_shape_rms = 0.002 }\n";
  {
    const ScratchFolder dir("clothbench-test-ensemble-");
    const fs::path p = fs::path(dir.path()) / "tolerances.toml";
    std::ofstream(p) << tolerance_text(table + detect + "max_seconds = 30\n");
    const Tolerances t = read_tolerances(p);
    const Tolerances::Ensemble& e = t.ensemble.at("bullet");
    CHECK(e.members == 0);
    CHECK(e.detect.at("final_shape_rms") == 0.002);
    CHECK(e.max_seconds == 30);
    std::ofstream(p) << tolerance_text(table + detect);
    CHECK(read_tolerances(p).ensemble.at("bullet").max_seconds == 60);
  }
  CHECK_THAT(refusal(tolerance_text(table + detect + "members = 8\n")),
             Catch::Contains("not both"));
  CHECK_THAT(refusal(tolerance_text(table + "detect = { final_com_y = 0.001 }\n")),
             Catch::Contains("no shift for \"final_shape_rms\""));
  CHECK_THAT(
      refusal(tolerance_text(table + "detect = { final_com_y = 0.001, final_shape_rms = 0.002, "
                                     "steps = 1 }\n")),
      Catch::Contains("detect.steps: not one of the ensemble's quantities"));
  for (const char* bad : {"0.0", "-1e-3", "nan", "inf", "\"1 mm\""})
    CHECK_THAT(refusal(tolerance_text(table + "detect = { final_com_y = " + bad +
                                      ", final_shape_rms = 0.002 }\n")),
               Catch::Contains("ensemble.bullet.detect.final_com_y: expected a finite shift > 0"));
  CHECK_THAT(refusal(tolerance_text(table + detect + "max_seconds = 0\n")),
             Catch::Contains("max_seconds: expected a time > 0"));
  CHECK_THAT(refusal(tolerance_text(table + "members = 8\nmax_seconds = 10\n")),
             Catch::Contains("only with detect"));
  CHECK_THAT(refusal(tolerance_text(table)), Catch::Contains("no members"));
}

namespace {

// the members check --update records for a goal, and the note of its final_com_y row
int recorded_members(const std::string& detect, std::string& note) {
  const ChainBaseline chain(
      "[ensemble.custom-symplectic-euler]\nreason = \"test\"\nquantities = [\"final_com_y\"]\n" +
      detect);
  CheckOptions o = chain.options;
  o.update = true;
  for (const Gate& g : check_scenario(chain.scenario, o))
    if (g.quantity == "final_com_y (mean)") note = g.note;
  const int n = int(read_ensemble((chain.base / "metrics_ensemble.csv").string())
                        .at("custom-symplectic-euler/final_com_y")
                        .size());
  // a check runs the recorded members and passes
  o.update = false;
  o.ensemble = true;
  for (const Gate& g : check_scenario(chain.scenario, o)) {
    INFO(g.quantity << ": " << g.note);
    CHECK(g.pass);
  }
  return n;
}

}  // namespace

TEST_CASE("check --update chooses the members from the spread, within max_seconds", "[ensemble]") {
  std::string note;
  // round-off spreads: a millimetre is caught by the fewest members
  CHECK(recorded_members("detect = { final_com_y = 1e-3 }\n", note) == kMinChosenMembers);
  CHECK_THAT(note, Catch::Contains("catches a shift of") && Catch::Contains("(goal 0.001)"));
  CHECK_THAT(note, !Catch::Contains("max_seconds"));
  // a goal below round-off is out of reach: the cap decides, and the note says so
  const int capped =
      recorded_members("detect = { final_com_y = 1e-30 }\nmax_seconds = 1e-9\n", note);
  CHECK(capped == kMinChosenMembers);
  CHECK_THAT(note, Catch::Contains("more members would cost over max_seconds = 1e-09 s"));
}
