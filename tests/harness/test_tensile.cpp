// The strip-tensile test and the grid's per-direction structural stiffness: the slope the
// harness measures on a known spring lattice against the lattice's closed form.

#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "cloth/model/model.hpp"
#include "harness/fabric/tensile_metrics.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario_error.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "tests/tolerances.hpp"

using namespace clothbench;

namespace {

/// A square lattice (spacing h = 12.5 mm, no bend springs, no gravity) 0.2 m long along the
/// pulled direction and 0.05 m across, clamped at one end and pulled 2 mm in 1 s at the other
/// (1 % strain), every particle held across the strip and out of its plane: the strain is
/// uniform, each spring's stretch known. along_u: pulled along the grid's u (x), else along v.
std::string lattice(bool along_u, const std::string& stiffness, const std::string& integrator,
                    double dt) {
  // the strip from 0 to 0.2 m along the pulled axis
  const std::string dims =
      along_u ? "particles = [17, 5]\nsize = [0.2, 0.05]\ncenter = [0.1, 0.0, 0.0]\n"
              : "particles = [5, 17]\nsize = [0.05, 0.2]\ncenter = [0.0, 0.0, 0.1]\n";
  // lateral (across) and out-of-plane (y) axes held everywhere but on the handle
  const std::string lateral =
      along_u ? "min = [-1.0, -1.0, -1.0]\nmax = [0.19, 1.0, 1.0]\nhold = \"yz\"\n"
              : "min = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 0.19]\nhold = \"xy\"\n";
  const std::string pull = along_u ? "[1.0, 0.002, 0.0, 0.0]" : "[1.0, 0.0, 0.0, 0.002]";
  // implicit-euler as the linearized step, which settles onto the closed form to round-off:
  // line-search (the default) stops at newton_tolerance: force errors up to 2.3e-4 measured
  const std::string newton =
      integrator == "implicit-euler" ? "newton = \"linearized\"\n" : std::string();
  return "name = \"lattice\"\nduration = 1.0\nframe_interval = 0.01\n"
         "gravity = [0.0, 0.0, 0.0]\n[cloth]\n" +
         dims +
         "plane = \"xz\"\nareal_density = 0.2\n"
         "stiffness = " +
         stiffness + "\ndamping = 0.05\n[[constraint]]\nselect = \"box\"\n" + lateral +
         "[[constraint]]\nselect = \"" + (along_u ? "edge:u0" : "edge:v0") +
         "\"\n[[handle]]\nselect = \"" + (along_u ? "edge:u1" : "edge:v1") +
         "\"\npath = [[0.0, 0.0, 0.0, 0.0], " + pull +
         "]\n[test]\nkind = \"strip-tensile\"\ndirection = \"" + (along_u ? "u" : "v") +
         "\"\nfit_strain = 0.01\n[[engine]]\nname = \"e\"\nkind = \"custom\"\nintegrator = \"" +
         integrator + "\"\ndt = " + std::to_string(dt) + "\n" + newton;
}

/// The closed form of the lattice stretched by strain e along its rows with no lateral motion,
/// per unit width W = (n - 1) h, n particles across: n springs k_s stretched by h e, and
/// 2 (n - 1) diagonals k_d from h sqrt(2) to l = h sqrt((1 + e)^2 + 1), each pulling with
/// k_d (l - h sqrt(2)) times the cosine h (1 + e) / l of its angle to the rows (N/m).
double lattice_force_per_width(double e, int n, double h, double ks, double kd) {
  const double l = h * std::sqrt((1 + e) * (1 + e) + 1);
  const double diagonal = kd * (l - h * std::sqrt(2.0)) * h * (1 + e) / l;
  return (n * ks * h * e + 2 * (n - 1) * diagonal) / ((n - 1) * h);
}

/// The harness's curve of the one engine of text.
std::vector<TensilePoint> measured_curve(const std::string& text, bool along_u) {
  const Scenario sc = parse_scenario(text, "<lattice>");
  RunOptions o;
  o.progress = false;
  const RunResult result = run_scenario(sc, o);
  REQUIRE(result.runs.size() == 1);
  REQUIRE(result.runs[0].stable);
  const cloth::Vector3 axis = along_u ? cloth::Vector3::UnitX() : cloth::Vector3::UnitZ();
  const TensileSetup setup =
      tensile_setup(result.model.x0, sc.scene.held, sc.scene.handles[0].particles, axis, 0.05);
  CHECK(setup.gauge == Approx(0.2).epsilon(1e-12));
  std::vector<double> t;
  for (const FrameMetrics& m : result.runs[0].frames) t.push_back(m.t);
  return tensile_curve(result.model.springs, result.model.x0, setup, sc.scene.handles[0].motion, t,
                       result.runs[0].positions);
}

}  // namespace

TEST_CASE("the strip-tensile slope of a spring lattice equals its closed form", "[tensile]") {
  const bool along_u = GENERATE(true, false);
  const std::string integrator = GENERATE(as<std::string>{}, "implicit-euler", "rk4");
  const double dt = integrator == "rk4" ? 1e-4 : 1e-3;
  // anisotropic: the pulled direction's structural springs are k_s, the other direction's 3 k_s
  const double ks = 100, kd = 50, h = 0.0125;
  const std::string stiffness =
      along_u ? "{ structural_u = 100.0, structural_v = 300.0, shear = 50.0 }"
              : "{ structural_u = 300.0, structural_v = 100.0, shear = 50.0 }";
  CAPTURE(along_u, integrator);
  const std::vector<TensilePoint> curve =
      measured_curve(lattice(along_u, stiffness, integrator, dt), along_u);
  // the closed form at the same strains, fitted the same way: the lattice's geometric
  // nonlinearity over the fit range is in both
  std::vector<TensilePoint> exact = curve;
  for (TensilePoint& p : exact) p.force_per_width = lattice_force_per_width(p.strain, 5, h, ks, kd);
  const double slope = tensile_slope(curve, 0.01);
  CHECK(slope == Approx(tensile_slope(exact, 0.01)).epsilon(tol::kTensileSlopeRelative));
  // the initial slope n / (n - 1) k_s + k_d of the linearised closed form (d l / d e = h / sqrt 2
  // at e = 0) differs from the fit by the nonlinearity alone
  CHECK(slope == Approx(5.0 / 4.0 * ks + kd).epsilon(tol::kTensileNonlinearRelative));
  // frame by frame once the tension wave of the handle's sudden start has died out
  for (const TensilePoint& p : curve)
    if (p.t >= 0.5)
      CHECK(p.force_per_width == Approx(lattice_force_per_width(p.strain, 5, h, ks, kd))
                                     .epsilon(tol::kTensileSettledRelative));
}

TEST_CASE("structural_u and structural_v set a grid's structural springs by direction",
          "[tensile][scenario]") {
  const std::string text =
      lattice(true, "{ structural_u = 100.0, structural_v = 300.0 }", "implicit-euler", 1e-3);
  const Scenario sc = parse_scenario(text, "<lattice>");
  const cloth::Model model = cloth::build_model(sc.scene);
  int along_u = 0, along_v = 0;
  for (const cloth::SpringLink& l : model.springs.links()) {
    REQUIRE(l.kind == cloth::SpringKind::structural);
    const cloth::Vector3 d = model.x0.col(l.b) - model.x0.col(l.a);
    if (std::abs(d.z()) < 1e-12) {
      CHECK(l.stiffness == 100.0);
      ++along_u;
    } else {
      CHECK(std::abs(d.x()) < 1e-12);
      CHECK(l.stiffness == 300.0);
      ++along_v;
    }
  }
  CHECK(along_u == 16 * 5);
  CHECK(along_v == 17 * 4);
  // the two forms together, and the per-direction keys on a mesh, are refused with the key
  auto refused = [&](const std::string& scene, const std::string& words) {
    try {
      (void)parse_scenario(scene, "<lattice>");
      FAIL("accepted");
    } catch (const ScenarioError& e) {
      CHECK_THAT(e.what(), Catch::Contains(words));
    }
  };
  refused(lattice(true, "{ structural = 1.0, structural_v = 300.0 }", "implicit-euler", 1e-3),
          "cloth.stiffness.structural_v");
  refused(lattice(true, "{ structural = 1.0, structural_u = 300.0 }", "implicit-euler", 1e-3),
          "both forms");
  const std::string mesh =
      "name = \"m\"\nduration = 0.1\n[cloth]\nareal_density = 0.2\n"
      "[cloth.generate]\n"
      "shape = \"disk\"\nradius = 0.1\nedge_length = 0.05\n"
      "[cloth.stiffness]\nstructural_u = 1.0\n"
      "[[engine]]\nkind = \"custom\"\nintegrator = \"rk4\"\ndt = 1e-4\n";
  refused(mesh, "stays isotropic");
  // a Bullet engine has one structural stiffness: refused by name
  refused(text + "[[engine]]\nname = \"b\"\nkind = \"bullet-softbody\"\ndt = 1e-3\n",
          "structural_u != structural_v");
}

TEST_CASE("a strip-tensile scene needs a clamp, one handle pulling along its direction, a grid",
          "[tensile][scenario]") {
  const std::string good = lattice(true, "{ structural = 100.0 }", "implicit-euler", 1e-3);
  REQUIRE_NOTHROW(parse_scenario(good, "<lattice>"));
  auto refused = [](const std::string& scene, const std::string& words) {
    INFO(words);
    try {
      (void)parse_scenario(scene, "<lattice>");
      FAIL("accepted");
    } catch (const ScenarioError& e) {
      CHECK_THAT(e.what(), Catch::Contains(words));
    }
  };
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const size_t at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
  };
  // pulled along v while the test measures along u, or pushed back
  refused(with("direction = \"u\"", "direction = \"v\""), "move forward along");
  refused(with("[1.0, 0.002, 0.0, 0.0]", "[1.0, -0.002, 0.0, 0.0]"), "move forward along");
  // no clamp: the end column held only across and out of plane
  refused(with("select = \"edge:u0\"", "select = \"edge:u0\"\nhold = \"y\""), "fixed clamp");
  // two handles (the column before the moving clamp freed for the second)
  refused(with("max = [0.19, 1.0, 1.0]", "max = [0.18, 1.0, 1.0]") +
              "[[handle]]\nselect = \"indices\"\nlist = [[15, 2]]\n",
          "expected one [[handle]]");
  // a bias-extension on a grid: its specimen is a generated lattice at 45 degrees
  refused(with("kind = \"strip-tensile\"\ndirection = \"u\"\nfit_strain = 0.01",
               "kind = \"bias-extension\""),
          "lattice_angle = 45");
}
