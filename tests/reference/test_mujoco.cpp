#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>

#include "cloth/forces/spring_forces.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "harness/scenario/scenario_error.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "reference/mujoco/mujoco_cloth.hpp"
#include "test_scenes.hpp"
#include "tolerances.hpp"

using namespace cloth;
using namespace clothbench::reference;
namespace tol = clothbench::tol;

namespace {

/// A mujoco engine with integrator i at step h.
std::unique_ptr<Simulator> mujoco(const Scene& s, MujocoIntegrator i, double h) {
  MujocoOptions o;
  o.integrator = i;
  return make_mujoco_cloth(o, h, s);
}

/// One spring (one_spring(m, k, c)) in a mujoco engine with integrator i at step h, set to a
/// stretched, moving state x, v; f is the custom engine's spring force there.
struct StretchedSpring {
  std::unique_ptr<Simulator> engine;
  Matrix3X x, v, f;
};

StretchedSpring stretched_spring(double m, double k, double c, MujocoIntegrator i, double h) {
  const Scene s = clothbench::test::one_spring(m, k, c);
  StretchedSpring r{mujoco(s, i, h), {}, Matrix3X::Zero(3, 2), Matrix3X::Zero(3, 2)};
  r.x = r.engine->positions();
  r.x.col(1) += Vector3(0.07, -0.03, 0.02);
  r.v.col(1) = Vector3(0.4, 0.9, -0.3);
  r.engine->set_state(r.x, r.v, 0.0);
  Matrix3X buf(3, 2);
  add_spring_forces(build_model(s).springs, r.x, r.v, r.f, buf);
  return r;
}

/// A 5 x 5 cloth with damped springs, air drag and wind: every force MuJoCo's explicit
/// integrators apply.
Scene windy_cloth() {
  Scene s = clothbench::test::small_cloth(5, 200.0, 0.5);
  s.cloth.air_drag = 0.05;
  s.wind = {1.0, 0.0, 0.5};
  return s;
}

/// Two engines run side by side: both at the end, and their largest position difference.
struct SideBySide {
  std::unique_ptr<Simulator> mj;
  std::unique_ptr<MassSpringCloth> custom;
  double worst = 0.0;  // m
};

/// MuJoCo's integrator mj and the custom engine's custom_integrator side by side on scene s for
/// 1 s in steps of h.
SideBySide side_by_side(const Scene& s, MujocoIntegrator mj, Integrator custom_integrator,
                        double h) {
  SolverOptions o;
  o.integrator = custom_integrator;
  SideBySide r{mujoco(s, mj, h), std::make_unique<MassSpringCloth>(s, o), 0.0};
  for (int i = 0; i < static_cast<int>(std::lround(1.0 / h)); ++i) {
    r.mj->step(h);
    r.custom->step(h);
    r.worst = std::max(r.worst, (r.mj->positions() - r.custom->positions()).cwiseAbs().maxCoeff());
  }
  return r;
}

}  // namespace

TEST_CASE("mujoco: free fall follows y0 - g t^2 / 2 with each scheme's known offset", "[mujoco]") {
  const MujocoIntegrator integrator = GENERATE(from_range(all_mujoco_integrators()));
  // a cloth without held particles falls rigidly: its tendons stay at rest length
  Scene s = clothbench::test::small_cloth(4, 500.0, 2.0);
  s.held.clear();
  const double g = 9.8, h = 1e-3;
  const int steps = 1000;
  auto c = mujoco(s, integrator, h);
  const double y0 = c->positions().row(1).mean();
  for (int i = 0; i < steps; ++i) c->step(h);
  const double t = steps * h;
  const double exact = y0 - 0.5 * g * t * t;
  // euler and implicit update v first, then x with the new v: they lead by g h t / 2
  const double expected = integrator == MujocoIntegrator::rk4 ? exact : exact - 0.5 * g * h * t;
  INFO(mujoco_integrator_name(integrator));
  CHECK(c->positions().row(1).mean() == Approx(expected).margin(tol::kFreeFallOffset));
  CHECK(c->time() == Approx(t));
}

TEST_CASE("mujoco: a stretched, moving spring's tendon force is the report's", "[mujoco]") {
  // one Euler step from a stretched, moving state changes the velocity by h f / m exactly
  const double m = 0.2, h = 1e-3;
  auto [e, x, v, f] = stretched_spring(m, 300.0, 1.5, MujocoIntegrator::euler, h);
  e->step(h);
  const Vector3 dv = e->velocities().col(1) - v.col(1);
  INFO("mujoco dv " << dv.transpose() << ", h f / m " << (h * f.col(1) / m).transpose());
  CHECK((dv - h * f.col(1) / m).norm() <= tol::kMujocoRoundOff);
  CHECK((e->positions().col(1) - x.col(1) - h * e->velocities().col(1)).norm() <=
        tol::kMujocoRoundOff);
}

TEST_CASE("mujoco: a hanging chain settles where discrete statics put it", "[mujoco]") {
  const MujocoIntegrator integrator = GENERATE(MujocoIntegrator::euler, MujocoIntegrator::implicit);
  const int n = 10;
  const double m = 0.1, k = 100.0, l = 0.1, g = 9.8;
  const Scene s = clothbench::test::chain(n, m, k, l, 5.0, g);
  const double h = 1e-3;
  auto c = mujoco(s, integrator, h);
  for (int i = 0; i < static_cast<int>(30.0 / h); ++i) c->step(h);
  const Matrix3X& x = c->positions();
  INFO(mujoco_integrator_name(integrator));
  // the spring above particle j carries the j + 1 particles below it: stretch (j + 1) m g / k
  for (int j = 0; j < n; ++j) {
    const double stretch = (x.col(j + 1) - x.col(j)).norm() - l;
    CHECK(stretch == Approx((j + 1) * m * g / k).epsilon(tol::kStaticStretchRelative));
  }
}

TEST_CASE("mujoco: a chain oscillates at its analytic lowest eigenfrequency", "[mujoco]") {
  const MujocoIntegrator integrator = GENERATE(MujocoIntegrator::rk4, MujocoIntegrator::euler);
  const int n = 10;
  const double m = 0.1, k = 100.0, l = 0.1;
  const Scene s = clothbench::test::chain(n, m, k, l, 0.0, 0.0);
  // fixed at the top, free at the bottom: u_s = sin(s theta), theta = pi / (2n + 1),
  // omega = 2 sqrt(k / m) sin(theta / 2), s counting particles down from the pin
  const double theta = M_PI / (2 * n + 1);
  const double omega = 2.0 * std::sqrt(k / m) * std::sin(theta / 2);
  const double h = 1e-4, period = 2 * M_PI / omega;
  auto c = mujoco(s, integrator, h);
  Matrix3X v = Matrix3X::Zero(3, n + 1);
  for (int j = 0; j < n; ++j) v(1, j) = 0.01 * std::sin((n - j) * theta);
  c->set_state(c->positions(), v, 0.0);
  const double y_rest = c->positions()(1, 0);
  // time the upward zero crossings of the bottom particle's displacement
  double previous = 0.0, first = -1.0, last = -1.0;
  int crossings = 0;
  for (int i = 0; i < static_cast<int>(6 * period / h); ++i) {
    c->step(h);
    const double d = c->positions()(1, 0) - y_rest;
    if (previous < 0 && d >= 0) {
      const double t = c->time() - h * d / (d - previous);  // linear interpolation
      if (first < 0) first = t;
      last = t;
      ++crossings;
    }
    previous = d;
  }
  REQUIRE(crossings >= 5);
  const double measured = 2 * M_PI * (crossings - 1) / (last - first);
  INFO(mujoco_integrator_name(integrator)
       << ": measured " << measured << " rad/s, analytic " << omega);
  CHECK(measured == Approx(omega).epsilon(tol::kEigenfrequencyRelative));
}

TEST_CASE("mujoco: euler matches the custom symplectic euler on a small cloth without contact",
          "[mujoco]") {
  const SideBySide r =
      side_by_side(windy_cloth(), MujocoIntegrator::euler, Integrator::symplectic_euler, 1e-3);
  INFO("largest position difference over 1 s: " << r.worst << " m");
  CHECK(r.worst <= tol::kMujocoEulerMatch);
  CHECK((r.mj->velocities() - r.custom->velocities()).cwiseAbs().maxCoeff() <=
        tol::kMujocoEulerMatchVelocity);
}

TEST_CASE("mujoco: implicit is backward Euler in the damping of a spring to a pin", "[mujoco]") {
  // one step from a stretched, moving state solves (m I + h c n n^T) dv = h f(x, v): the
  // damping force's velocity derivative -c n n^T is implicit, the spring force explicit (the
  // other end is pinned, so the derivative has no coupling block; see the next test)
  const double m = 0.2, c = 4.0, h = 1e-2;
  auto [e, x, v, f] = stretched_spring(m, 300.0, c, MujocoIntegrator::implicit, h);
  const Vector3 n = (x.col(1) - x.col(0)).normalized();
  const Eigen::Matrix3d a = m * Eigen::Matrix3d::Identity() + h * c * n * n.transpose();
  const Vector3 expected = a.lu().solve(h * f.col(1));
  e->step(h);
  const Vector3 dv = e->velocities().col(1) - v.col(1);
  INFO("mujoco dv " << dv.transpose() << ", expected " << expected.transpose() << ", explicit "
                    << (h * f.col(1) / m).transpose());
  CHECK((dv - expected).norm() <= tol::kMujocoRoundOff);
}

TEST_CASE("mujoco: set_state then a step equals the run's own step", "[mujoco]") {
  const MujocoIntegrator integrator = GENERATE(from_range(all_mujoco_integrators()));
  const Scene s = clothbench::test::small_cloth(5, 200.0, 0.5);
  const double h = 1e-3;
  auto run = mujoco(s, integrator, h);
  for (int i = 0; i < 100; ++i) run->step(h);
  auto fresh = mujoco(s, integrator, h);
  fresh->set_state(run->positions(), run->velocities(), run->time());
  run->step(h);
  fresh->step(h);
  INFO(mujoco_integrator_name(integrator));
  CHECK((run->positions() - fresh->positions()).cwiseAbs().maxCoeff() <= tol::kMujocoRoundOff);
  CHECK(fresh->time() == Approx(run->time()));
}

TEST_CASE("mujoco: a cloth at rest on a floor is held at the margin by its weight", "[mujoco]") {
  // a 5 x 5 cloth lying flat just above a frictional floor settles on its contacts: the floor's
  // impulse over the last second equals the weight times that second
  Scene s = clothbench::test::small_cloth(5, 200.0, 0.5);
  s.held.clear();
  cloth::HalfSpace floor;
  floor.point = {0.0, -0.02, 0.0};
  floor.friction = 0.5;
  floor.margin = 0.01;
  s.shapes.planes.push_back(floor);
  const double h = 1e-3;
  auto c = mujoco(s, MujocoIntegrator::euler, h);
  for (int i = 0; i < 1000; ++i) c->step(h);
  const Vector3 before = c->contact_impulse();
  for (int i = 0; i < 1000; ++i) c->step(h);
  const double weight = 25 * 0.1 * 9.8;
  CHECK(c->contacts() == 25);
  CHECK((c->contact_impulse() - before).y() ==
        Approx(weight * 1.0).epsilon(tol::kMujocoRestingImpulse));
  // every particle rests in the shell: above the plane, within the margin of it
  const Eigen::ArrayXd gap = c->positions().row(1).array() + 0.02;
  CHECK(gap.minCoeff() > 0.0);
  CHECK(gap.maxCoeff() < floor.margin);
}

TEST_CASE("mujoco: the memory estimate bounds what MuJoCo allocates", "[mujoco]") {
  // the seed scene's cloth with its sphere at 12 x 12: the estimate is built from the same
  // sizes MuJoCo allocates from, so it must be close to the measured model, buffer and stack
  const MujocoIntegrator integrator = GENERATE(from_range(all_mujoco_integrators()));
  MujocoOptions o;
  o.integrator = integrator;
  const Scene s = seed_scene(12);
  auto e = make_mujoco_cloth(o, 1e-3, s);
  const MujocoMeasure m = mujoco_measure(*e);
  INFO(mujoco_integrator_name(integrator)
       << ": buffer " << m.buffer_bytes << " estimated " << m.size.buffer_bytes << ", model "
       << m.model_bytes << " estimated " << m.size.model_bytes);
  CHECK(m.size.buffer_bytes == Approx(m.buffer_bytes).epsilon(tol::kMujocoMemoryEstimate));
  CHECK(m.size.model_bytes == Approx(m.model_bytes).epsilon(tol::kMujocoMemoryEstimate));
  CHECK(m.stack_bytes == Approx(8.0 * double(m.size.stack)));
}

TEST_CASE("mujoco: a cloth whose dense arrays pass the limit is refused with the reason",
          "[mujoco]") {
  const auto refusal = mujoco_refusal(MujocoOptions{}, seed_scene(64));
  REQUIRE(refusal);
  CHECK_THAT(refusal->why, Catch::Contains("densely") && Catch::Contains("springs by") &&
                               Catch::Contains("constraint Jacobian"));
  CHECK_FALSE(mujoco_refusal(MujocoOptions{}, seed_scene(25)));
}

TEST_CASE("mujoco: the scenario loader reads its keys and refuses what it cannot model",
          "[mujoco][scenario]") {
  const std::string head =
      "duration = 0.01\n[cloth]\nparticles = [4, 4]\n[[sphere]]\ncenter = [0, 0, 0]\n"
      "radius = 0.5\n";
  const std::string engine = "[[engine]]\nname = \"m\"\nkind = \"mujoco\"\n";
  const clothbench::Scenario s = clothbench::parse_scenario(
      head + engine +
          "integrator = \"implicit\"\nmargin = 0.02\nfriction = 0.3\nsolref = [0.01, 0.5]\n"
          "solimp = [0.8, 0.9, 0.002]\ncone = \"elliptic\"\n",
      "m.toml");
  const MujocoOptions& o = s.engines.at(0).mujoco;
  CHECK(o.integrator == MujocoIntegrator::implicit);
  CHECK(o.margin == 0.02);
  CHECK(o.friction == 0.3);
  CHECK(o.solref == std::array<double, 2>{0.01, 0.5});
  CHECK(o.solimp == std::array<double, 3>{0.8, 0.9, 0.002});
  CHECK(o.elliptic);
  // restitution and an explicit self_collision are refused when the scenario loads
  CHECK_THROWS_AS(clothbench::parse_scenario(head + "restitution = 0.5\n" + engine, "r.toml"),
                  clothbench::ScenarioError);
  CHECK_THROWS_WITH(clothbench::parse_scenario(head + engine + "self_collision = true\n", "s.toml"),
                    Catch::Contains("mujoco cannot keep a cloth's layers apart"));
}

TEST_CASE("mujoco: implicit keeps only each particle's own block of the damping derivative",
          "[mujoco]") {
  // two free particles on a damped spring: 2.2.2's implicit step solves with M - h D where D
  // keeps the tendon damping's derivative only within each body's dofs (M's sparsity), not
  // the -c n n^T coupling between the two particles, so it is not backward Euler in the
  // damping once both ends move
  const double m = 0.2, c = 4.0, h = 1e-2;
  Scene s = clothbench::test::one_spring(m, 300.0, c);
  s.held.clear();
  auto e = mujoco(s, MujocoIntegrator::implicit, h);
  Matrix3X x = e->positions(), v = Matrix3X::Zero(3, 2);
  x.col(1) += Vector3(0.07, -0.03, 0.02);
  v.col(1) = Vector3(0.4, 0.9, -0.3);
  v.col(0) = Vector3(-0.2, 0.1, 0.3);
  e->set_state(x, v, 0.0);
  Matrix3X f = Matrix3X::Zero(3, 2), buf(3, 2);
  add_spring_forces(build_model(s).springs, x, v, f, buf);
  const Vector3 n = (x.col(1) - x.col(0)).normalized();
  const Eigen::Matrix3d block = h * c * n * n.transpose();
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  Matrix6 own = m * Matrix6::Identity();
  own.block<3, 3>(0, 0) += block;
  own.block<3, 3>(3, 3) += block;
  Matrix6 coupled = own;
  coupled.block<3, 3>(0, 3) -= block;
  coupled.block<3, 3>(3, 0) -= block;
  Vector6 rhs;
  rhs << h * f.col(0), h * f.col(1);
  e->step(h);
  Vector6 dv;
  dv << e->velocities().col(0) - v.col(0), e->velocities().col(1) - v.col(1);
  const Vector6 by_own = own.lu().solve(rhs), backward = coupled.lu().solve(rhs);
  INFO("mujoco " << dv.transpose() << "\nown blocks " << by_own.transpose()
                 << "\nbackward Euler in the damping " << backward.transpose());
  CHECK((dv - by_own).norm() <= tol::kMujocoRoundOff);
  CHECK((dv - backward).norm() > 0.1);
}

TEST_CASE("mujoco: rk4 with air drag and wind follows the custom rk4 step for step", "[mujoco]") {
  // the drag -c (v - w) depends on the velocity at each of rk4's four stages: held at the
  // step's start (as a force applied once a step) it would leave the step first order
  const SideBySide r = side_by_side(windy_cloth(), MujocoIntegrator::rk4, Integrator::rk4, 4e-3);
  INFO("largest position difference over 1 s: " << r.worst << " m");
  CHECK(r.worst <= tol::kMujocoEulerMatch);
}
