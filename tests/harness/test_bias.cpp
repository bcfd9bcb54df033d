// The bias-extension test: the pin-jointed-net angle relation and the measured central angle
// on a pin-jointed shear of the 45-degree lattice, and the shear stiffness the harness
// measures on a known spring lattice against the lattice's closed form.

#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "cloth/model/mesh_generator.hpp"
#include "cloth/model/model.hpp"
#include "harness/fabric/bias_metrics.hpp"
#include "harness/run/engine_metric.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario_error.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_writer.hpp"
#include "tests/tolerances.hpp"

using namespace clothbench;

namespace {

constexpr double kH = 0.15, kW = 0.05;  // m, the specimen's length (x) and width (z)

/// The bias specimen, 150 mm x 50 mm in the xz plane from x = 0 to 0.15, yarns at 45 degrees
/// (5 mm half-diagonal steps), clamped at x = 0 and pulled along +x by d_max in duration;
/// structural (yarn) springs ky, shear (diagonal) springs ks, no bend springs, no gravity.
std::string specimen(double ky, double ks, double d_max, double duration) {
  return "name = \"bias\"\nduration = " + std::to_string(duration) +
         "\nframe_interval = 0.01\ngravity = [0.0, 0.0, 0.0]\n"
         "[cloth]\nareal_density = 0.2\ndamping = 0.002\n"
         "stiffness = { structural = " +
         std::to_string(ky) + ", shear = " + std::to_string(ks) +
         " }\n[cloth.generate]\nshape = \"rectangle\"\nsize = [0.15, 0.05]\n"
         "edge_length = 0.00707106781186548\ncenter = [0.075, 0.5, 0.0]\nplane = \"xz\"\n"
         "lattice = \"grid\"\nlattice_angle = 45.0\n"
         "[[constraint]]\nselect = \"box\"\nmin = [-0.001, 0.0, -1.0]\nmax = [0.001, 1.0, 1.0]\n"
         "[[handle]]\nselect = \"box\"\nmin = [0.149, 0.0, -1.0]\nmax = [0.151, 1.0, 1.0]\n"
         "path = [[0.0, 0.0, 0.0, 0.0], [" +
         std::to_string(duration) + ", " + std::to_string(d_max) +
         ", 0.0, 0.0]]\n[test]\nkind = \"bias-extension\"\nfit_angle = 5.0\n"
         "[[engine]]\nname = \"e\"\nkind = \"custom\"\nintegrator = \"implicit-euler\"\n"
         "dt = 1e-3\n";
}

/// The rest positions of the specimen's lattice.
cloth::Matrix3X rest_lattice() {
  cloth::ShapeSpec s;
  s.shape = cloth::MeshShape::rectangle;
  s.lattice = cloth::MeshLattice::grid;
  s.lattice_angle = 45.0;
  s.size_u = kH;
  s.size_v = kW;
  s.edge_length = 0.005 * std::sqrt(2.0);
  s.center = {kH / 2, 0.5, 0.0};
  return cloth::generate_mesh(s).x;
}

}  // namespace

TEST_CASE("a pin-jointed shear of the lattice gives its angle by the relation and measured",
          "[bias]") {
  const double gamma = GENERATE(0.01, 0.1, 0.4, 0.8);  // rad
  CAPTURE(gamma);
  const cloth::Matrix3X x0 = rest_lattice();
  std::vector<std::uint8_t> held(size_t(x0.cols()), 0);
  std::vector<int> handle;
  for (Eigen::Index p = 0; p < x0.cols(); ++p) {
    if (x0(0, p) == 0.0) held[size_t(p)] = cloth::kHoldAll;
    if (x0(0, p) == kH) handle.push_back(int(p));
  }
  const BiasSetup setup =
      bias_setup(x0, held, handle, cloth::Vector3::UnitX(), cloth::Vector3::UnitZ());
  CHECK(setup.length == kH);
  CHECK(setup.width == kW);
  // a rhombus of unit sides at +-(pi/4 - gamma/2) to x: the yarns keep their length and the
  // angle between them closes from pi/2 by gamma
  const double half = M_PI / 4 - gamma / 2;
  const double stretch = std::sqrt(2.0) * std::cos(half), squeeze = std::sqrt(2.0) * std::sin(half);
  CHECK(stretch * stretch + squeeze * squeeze == Approx(2.0).epsilon(1e-15));
  // that shear about the centre, the sheet turned out of its plane too (the angle is 3-D)
  const cloth::Vector3 c(kH / 2, 0.5, 0.0);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.3, cloth::Vector3(0, 0, 1)).toRotationMatrix();
  cloth::Matrix3X x = x0;
  for (Eigen::Index p = 0; p < x.cols(); ++p) {
    const cloth::Vector3 r = x0.col(p) - c;
    x.col(p) = c + turn * cloth::Vector3(stretch * r.x(), r.y(), squeeze * r.z());
  }
  CHECK(central_shear_angle(x0, x, setup) == Approx(gamma).epsilon(1e-12));
  // the net's clamp zones are rigid triangles reaching W/2 along the centre line, so the
  // central zone spans H - W of it and the clamp moves by (H - W) (stretch - 1)
  const double d = (kH - kW) * (stretch - 1);
  CHECK(pin_jointed_angle(kH, kW, d) == Approx(gamma).epsilon(1e-12));
  CHECK(pin_jointed_angle(kH, kW, 0.0) == Approx(0.0).margin(1e-15));
}

TEST_CASE("the normalised shear force of a linear net gives back its shear stiffness", "[bias]") {
  // the energy balance run forward: a net of torque T = G gamma per unit area, F_s = T / cos,
  // clamp force F = [W (H - 3W/2) T(g) + W^2 T(g/2) / 2] / ((H - W) (cos g/2 - sin g/2) / 2)
  const double g_stiff = 3.7;  // N/m per rad
  std::vector<double> angle, force;
  for (int k = 1; k <= 40; ++k) {
    const double g = 0.005 * k;
    const double power = kW * (kH - 1.5 * kW) * g_stiff * g + kW * kW * g_stiff * g / 2 / 2;
    angle.push_back(g);
    force.push_back(power / ((kH - kW) * (std::cos(g / 2) - std::sin(g / 2)) / 2));
  }
  const std::vector<double> fs = normalise_shear_force(angle, force, kH, kW);
  REQUIRE(fs.size() == angle.size());
  for (size_t k = 0; k < fs.size(); ++k) {
    CAPTURE(angle[k]);
    // F_s(g/2) interpolated between the points: exact for a torque linear in the angle up to
    // the curvature of 1 / cos over one step (and the first point's F_s(g) / 2)
    CHECK(fs[k] * std::cos(angle[k]) == Approx(g_stiff * angle[k]).epsilon(2e-4));
  }
}

TEST_CASE("the bias-extension shear stiffness of a spring lattice equals its closed form",
          "[bias]") {
  // closed form: in a square of side h sheared by gamma (yarns inextensible) the diagonals
  // are 2 h cos(pi/4 -+ gamma/2) = sqrt(2) h (cos(gamma/2) +- sin(gamma/2)); two shear springs
  // k_s from sqrt(2) h store 4 k_s h^2 (1 - cos(gamma/2)): per unit area the torque is
  // 2 k_s sin(gamma/2), slope k_s at gamma = 0. A half square on the free edge has one
  // diagonal (along the edge) in half the area: the same energy per area. So the slope of
  // shear force per unit length against the angle is k_s, in N/m per rad.
  // yarns 4e4 times stiffer than the diagonals: nearly inextensible
  const double ks = 2.0, ky = 80000.0;
  // 11 degrees of pin-jointed shear: d = (H - W) (sqrt 2 cos(pi/4 - 5.5 deg) - 1) = 9.2 mm
  const Scenario sc = parse_scenario(specimen(ky, ks, 0.0092, 4.0), "<bias>");
  RunOptions o;
  o.progress = false;
  const RunResult result = run_scenario(sc, o);
  REQUIRE(result.runs.size() == 1);
  REQUIRE(result.runs[0].stable);
  const std::vector<BiasPoint> curve = bias_extension_curve(result, result.runs[0]);
  REQUIRE(curve.size() > 100);
  // the normalisation at the pin-jointed angle: the net's work against its kinematics
  CHECK(shear_slope(curve, 5.0, true) == Approx(ks).epsilon(tol::kBiasShearStiffnessRelative));
  // (at the central square's measured angle the slope is 19 % higher: that square shears
  // less than the zone around it, docs/methods.md; not a closed form, so not checked here)
}

TEST_CASE("a bias-extension scene needs its 45-degree lattice, a clamp and one handle along x",
          "[bias][scenario]") {
  const std::string good = specimen(200.0, 2.0, 0.005, 1.0);
  REQUIRE_NOTHROW(parse_scenario(good, "<bias>"));
  auto refused = [](const std::string& scene, const std::string& words) {
    INFO(words);
    try {
      (void)parse_scenario(scene, "<bias>");
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
  refused(with("lattice_angle = 45.0", "lattice_angle = 0.0"), "lattice_angle = 45");
  refused(with("lattice_angle = 45.0", "lattice_angle = 30.0"), "a multiple of 45");
  const auto triangular = [&](const std::string& s) {
    std::string out = s;
    out.replace(out.find("lattice = "),
                std::string("lattice = \"grid\"\nlattice_angle = 45.0\n").size(), "");
    return out;
  };
  const std::string no_shear = with(", shear = 2.000000", "");
  refused(triangular(no_shear), "lattice = \"grid\" and lattice_angle = 45");
  refused(with("size = [0.15, 0.05]", "size = [0.15, 0.08]"), "at least twice as long");
  refused(with("0.005000, 0.0, 0.0]]", "-0.005000, 0.0, 0.0]]"), "forward along x");
  refused(with("select = \"box\"\nmin = [-0.001", "hold = \"y\"\nselect = \"box\"\nmin = [-0.001"),
          "fixed clamp");
  refused(with("fit_angle = 5.0", "fit_strain = 0.01"), "no fit_strain");
  // shear springs on a lattice mesh are read; on another mesh refused
  const Scenario sc = parse_scenario(good, "<bias>");
  CHECK(sc.scene.cloth.k_shear == 2.0);
  // the resolved scenario (run's scenario.toml) reads back to the same lattice, springs, test
  const Scenario back = parse_scenario(scenario_to_toml(sc), "back.toml");
  CHECK(back.scene.cloth.k_shear == 2.0);
  CHECK(back.mesh.shape.lattice == cloth::MeshLattice::grid);
  CHECK(back.mesh.shape.lattice_angle == 45.0);
  CHECK(back.test.fit_angle == 5.0);
  CHECK(cloth::build_model(back.scene).springs.links().size() ==
        cloth::build_model(sc.scene).springs.links().size());
  refused(triangular(good), "cloth.stiffness.shear");
  // a fabric preset is mapped onto grids and triangle meshes, not onto a grid lattice
  refused(with("[cloth]\n", "[cloth]\nfabric = \"11oz-black-denim\"\n"), "expected no fabric");
}
