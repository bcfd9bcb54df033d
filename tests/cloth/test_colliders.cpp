#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <vector>

#include "cloth/contact/colliders.hpp"
#include "cloth/forces/energies.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "harness/engines/engine_factory.hpp"
#include "harness/scenario/engine_refusal.hpp"

using namespace cloth;

namespace {

// Tolerances of the collider tests, each with where it comes from.
/// Central differences with step 1e-6 m of a distance that is smooth away from edges:
/// truncation O(step^2 / curvature radius), round-off O(eps / step) ~ 1e-10.
constexpr double kGradient = 1e-6;
/// The requirements.
constexpr double kWeightRelative = 0.005;
constexpr double kSlideRelative = 0.01;
constexpr double kStickDistance = 1e-3;  // m over 1 s
constexpr double kHandleCustom = 1e-12;  // m
constexpr double kHandleBullet = 1e-9;   // m
constexpr double kTerminalRelative = 0.001;
/// A particle ends a step on or outside the shell; round-off in the projection only.
constexpr double kShellRoundoff = 1e-9;  // m

constexpr double kG = 9.8;  // m/s^2

// a 1 m square cloth of 9 x 9 particles, 1 kg, soft springs, lying flat at height y
Scene flat_cloth(double y) {
  Scene s;
  s.cloth.nu = s.cloth.nv = 9;
  s.cloth.size_u = s.cloth.size_v = 1.0;
  s.cloth.center = {0.0, y, 0.0};
  s.cloth.total_mass = 1.0;
  s.cloth.k_structural = s.cloth.k_shear = s.cloth.k_bend = 200.0;
  s.cloth.damping = 1.0;
  s.gravity = {0.0, -kG, 0.0};
  return s;
}

HalfSpace floor_plane(double friction) {
  HalfSpace p;
  p.friction = friction;
  return p;
}

Vector3 com(const MassSpringCloth& c) {
  return c.positions().rowwise().mean();  // equal masses
}

template <class Shape>
void check_gradient(const Shape& s, double t, const Vector3& x) {
  const SurfacePoint sp = surface_point(s, t, x);
  Vector3 grad;
  for (int a = 0; a < 3; ++a) {
    Vector3 e = Vector3::Zero();
    e[a] = 1e-6;
    grad[a] = (surface_point(s, t, x + e).distance - surface_point(s, t, x - e).distance) / 2e-6;
  }
  INFO("x = " << x.transpose() << ", n = " << sp.normal.transpose());
  CHECK((grad - sp.normal).norm() < kGradient);
  CHECK(std::abs(sp.normal.norm() - 1.0) < 1e-12);
}

}  // namespace

TEST_CASE("signed distances and normals match known points and finite differences", "[colliders]") {
  HalfSpace plane;
  plane.point = {0.0, 1.0, 0.0};
  plane.normal = Vector3(1.0, 1.0, 0.0).normalized();
  plane.velocity = {0.0, 1.0, 0.0};
  CHECK(surface_point(plane, 0.0, {0.0, 1.0, 0.0}).distance == Approx(0.0).margin(1e-15));
  CHECK(surface_point(plane, 1.0, {0.0, 3.0, 0.0}).distance == Approx(std::sqrt(0.5)));

  Box box;
  box.center = {1.0, 0.0, 0.0};
  box.half_extents = {0.5, 0.2, 0.3};
  CHECK(surface_point(box, 0.0, {1.0, 0.5, 0.0}).distance == Approx(0.3));
  CHECK(surface_point(box, 0.0, {1.0, 0.1, 0.0}).distance == Approx(-0.1));
  CHECK(surface_point(box, 0.0, {2.5, 1.2, 0.0}).distance == Approx(std::sqrt(2.0)));  // corner
  CHECK(surface_point(box, 0.0, {1.0, 0.1, 0.0}).normal == Vector3(0.0, 1.0, 0.0));

  Capsule cap;
  cap.a = {0.0, 0.0, 0.0};
  cap.b = {2.0, 0.0, 0.0};
  cap.radius = 0.1;
  CHECK(surface_point(cap, 0.0, {1.0, 0.5, 0.0}).distance == Approx(0.4));
  CHECK(surface_point(cap, 0.0, {3.0, 0.0, 0.0}).distance == Approx(0.9));  // beyond b
  CHECK(surface_point(cap, 0.0, {1.0, 0.05, 0.0}).distance == Approx(-0.05));

  Cylinder cyl;
  cyl.center = {0.0, 0.5, 0.0};
  cyl.radius = 0.2;
  cyl.height = 0.1;
  cyl.path = {{0.0, 0.0, 0.0, 0.0}, {1.0, 1.0, 0.0, 0.0}};
  CHECK(surface_point(cyl, 0.0, {0.0, 0.6, 0.0}).distance == Approx(0.05));    // above the top
  CHECK(surface_point(cyl, 0.0, {0.5, 0.5, 0.0}).distance == Approx(0.3));     // beside
  CHECK(surface_point(cyl, 0.0, {0.0, 0.52, 0.0}).distance == Approx(-0.03));  // inside
  CHECK(surface_point(cyl, 0.5, {0.5, 0.6, 0.0}).distance == Approx(0.05));    // moved by 0.5 m
  CHECK(surface_point(cyl, 0.0, {0.5, 0.95, 0.0}).distance == Approx(0.5));    // past the rim

  // the normal is the distance's gradient wherever the distance is smooth
  const std::vector<Vector3> points = {{0.3, 1.7, -0.4}, {1.1, 0.05, 0.1},    {2.2, -0.7, 0.9},
                                       {0.5, 0.62, 0.1}, {0.05, 0.52, -0.02}, {-0.6, 0.3, 0.25}};
  for (const Vector3& x : points) {
    check_gradient(plane, 0.3, x);
    check_gradient(box, 0.0, x);
    check_gradient(cap, 0.0, x);
    check_gradient(cyl, 0.25, x);
  }
}

TEST_CASE("a path is piecewise linear and held after its last point", "[colliders]") {
  Motion m;
  m.path = {{0.0, 0.0, 0.0, 0.0}, {1.0, 0.0, 0.5, 0.0}, {3.0, 1.0, 0.5, 0.0}};
  CHECK((m.displacement(0.5) - Vector3(0.0, 0.25, 0.0)).norm() < 1e-15);
  CHECK((m.displacement(2.0) - Vector3(0.5, 0.5, 0.0)).norm() < 1e-15);
  CHECK((m.displacement(7.0) - Vector3(1.0, 0.5, 0.0)).norm() < 1e-15);
  CHECK((m.velocity_at(1.0) - Vector3(0.5, 0.0, 0.0)).norm() < 1e-15);
  CHECK(m.velocity_at(3.0).isZero());
}

TEST_CASE("a cloth resting on a floor presses on it with its weight", "[colliders][slow]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  Scene s = flat_cloth(0.05);
  s.shapes.planes.push_back(floor_plane(0.5));
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth c(s, o);
  const double h = 1e-3;
  for (int i = 0; i < 2000; ++i) c.step(h);  // dropped 4 cm, settled
  const Vector3 before = c.contact_impulse();
  double lowest = INFINITY;
  for (int i = 0; i < 500; ++i) {
    c.step(h);
    lowest = std::min(lowest, c.positions().row(1).minCoeff());
  }
  const Vector3 force = (c.contact_impulse() - before) / (500 * h);
  INFO(integrator_name(integrator) << ": contact force " << force.transpose() << " N");
  CHECK(std::abs(force.y() - kG) < kWeightRelative * kG);
  CHECK(lowest >= s.shapes.planes[0].margin - 1e-9);
  CHECK(c.contacts() == c.model().particle_count());
}

TEST_CASE("Coulomb friction: a cloth on an incline sticks above tan(theta) and slides below",
          "[colliders]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  const double theta = 20.0 * M_PI / 180.0;
  const double h = 1e-3;
  for (const double mu : {std::tan(theta) + 0.02, 0.2}) {
    // the floor stays y = 0, gravity tilts: the cloth starts lying on the shell
    Scene s = flat_cloth(0.01);
    s.gravity = {kG * std::sin(theta), -kG * std::cos(theta), 0.0};
    s.shapes.planes.push_back(floor_plane(mu));
    SolverOptions o;
    o.integrator = integrator;
    MassSpringCloth c(s, o);
    const Vector3 start = com(c);
    for (int i = 0; i < 1000; ++i) c.step(h);
    const double moved = com(c).x() - start.x();
    INFO(integrator_name(integrator) << ", mu = " << mu << ": moved " << moved << " m");
    if (mu > std::tan(theta)) {
      CHECK(std::abs(moved) < kStickDistance);
    } else {
      // from rest: x = a t^2 / 2 after t = 1 s
      const double a = kG * (std::sin(theta) - mu * std::cos(theta));
      CHECK(std::abs(2.0 * moved - a) < kSlideRelative * a);
    }
  }
}

TEST_CASE("a moving box with friction 1 carries the cloth lying on it at its velocity",
          "[colliders]") {
  const Integrator integrator = GENERATE(Integrator::symplectic_euler, Integrator::implicit_euler);
  Scene s = flat_cloth(0.01);
  Box table;
  table.center = {0.0, -0.5, 0.0};
  table.half_extents = {3.0, 0.5, 3.0};
  table.friction = 1.0;
  table.velocity = {0.5, 0.0, 0.0};
  s.shapes.boxes.push_back(table);
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth c(s, o);
  for (int i = 0; i < 1000; ++i) c.step(1e-3);
  const Vector3 v = c.velocities().rowwise().mean();
  INFO(integrator_name(integrator) << ": cloth velocity " << v.transpose());
  CHECK(std::abs(v.x() - 0.5) < 1e-9);
  // it caught up within 0.5 / (mu g) = 51 ms, slipping by at most 0.5^2 / (2 mu g) = 1.3 cm
  CHECK(com(c).x() > 0.5 - 0.014);
  CHECK(com(c).x() < 0.5);
}

TEST_CASE("a capsule sweeping through a hanging cloth leaves no particle inside it",
          "[colliders]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  // a 1 m curtain hanging from its top edge in the x-y plane, a rod moving along z through it
  Scene s = flat_cloth(1.0);
  s.cloth.plane = Plane::xy;
  s.held.assign(size_t(s.particle_count()), 0);
  for (int i = 0; i < s.cloth.nu; ++i)
    s.held[size_t(particle_index(s.cloth, i, s.cloth.nv - 1))] = kHoldAll;
  Capsule rod;
  rod.a = {-1.0, 0.75, -0.3};  // at the height of a row of particles
  rod.b = {1.0, 0.75, -0.3};
  rod.radius = 0.1;
  rod.path = {{0.0, 0.0, 0.0, 0.0}, {1.0, 0.0, 0.0, 0.6}};
  s.shapes.capsules.push_back(rod);
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth c(s, o);
  double deepest = -INFINITY;
  for (int i = 0; i < 1500; ++i) {
    c.step(1e-3);
    for (Eigen::Index p = 0; p < c.positions().cols(); ++p)
      deepest = std::max(deepest, -surface_point(rod, c.time(), c.positions().col(p)).distance);
  }
  INFO(integrator_name(integrator));
  CHECK(deepest <= -rod.margin + kShellRoundoff);
  // the rod went through: it pushed the cloth ahead of it
  CHECK(c.positions().row(2).maxCoeff() > 0.2);
}

TEST_CASE("handles move their particles exactly along the path in every custom integrator",
          "[colliders]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  Scene s = flat_cloth(0.01);
  s.shapes.planes.push_back(floor_plane(0.3));
  Handle h;
  h.particles = {0, particle_index(s.cloth, 8, 0)};  // two corners
  h.motion.path = {{0.0, 0.0, 0.0, 0.0}, {0.5, 0.0, 0.5, 0.0}, {1.0, 0.4, 0.5, 0.0}};
  s.handles.push_back(h);
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth c(s, o);
  const Matrix3X x0 = c.positions();
  double worst = 0;
  for (int i = 0; i < 1000; ++i) {
    c.step(1e-3);
    for (int p : h.particles)
      worst = std::max(worst,
                       (c.positions().col(p) - x0.col(p) - h.motion.displacement(c.time())).norm());
  }
  INFO(integrator_name(integrator) << ": worst handle error " << worst << " m");
  CHECK(worst <= kHandleCustom);
  // the cloth followed: lifted by its corners, its centre of mass rose
  CHECK(com(c).y() > 0.1);
  // (the holder's work and the energy balance: tests/harness/test_handle_work.cpp)
}

TEST_CASE("a cloth falling in wind reaches wind + m g / c", "[colliders][.heavy]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  Scene s = flat_cloth(0.0);
  s.cloth.air_drag = 0.05;  // N s/m per particle; m = 1/81 kg: time constant 0.25 s
  s.wind = {3.0, 1.0, -2.0};
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth c(s, o);
  for (int i = 0; i < 6000; ++i) c.step(1e-3);
  const double m = 1.0 / 81.0;
  const Vector3 terminal = s.wind + m * s.gravity / s.cloth.air_drag;
  const Vector3 v = c.velocities().rowwise().mean();
  INFO(integrator_name(integrator)
       << ": v = " << v.transpose() << ", expected " << terminal.transpose());
  CHECK((v - terminal).norm() < kTerminalRelative * terminal.norm());
}

TEST_CASE("a scene without a shape makes no distance test for it", "[colliders]") {
  Scene s = flat_cloth(0.5);
  SolverOptions o;
  MassSpringCloth bare(s, o);
  for (int i = 0; i < 10; ++i) bare.step(1e-3);
  CHECK(bare.counters().contact_tests == 0);
  s.shapes.planes.push_back(floor_plane(0.0));
  s.shapes.cylinders.push_back(Cylinder{});
  MassSpringCloth two(s, o);
  for (int i = 0; i < 10; ++i) two.step(1e-3);
  CHECK(two.counters().contact_tests == 10 * 2 * s.particle_count());
}

TEST_CASE("Bullet engines: handles on their path and the wind's terminal velocity",
          "[colliders][bullet]") {
  const clothbench::EngineKind kind =
      GENERATE(clothbench::EngineKind::bullet_deformable, clothbench::EngineKind::bullet_softbody);
  clothbench::EngineSpec spec;
  spec.kind = kind;
  spec.dt = 1e-3;
  SECTION("handles") {
    Scene s = flat_cloth(0.5);
    Handle h;
    h.particles = {0, particle_index(s.cloth, 8, 0)};
    h.motion.path = {{0.0, 0.0, 0.0, 0.0}, {0.5, 0.0, 0.5, 0.0}, {1.0, 0.4, 0.5, 0.0}};
    s.handles.push_back(h);
    REQUIRE_FALSE(clothbench::engine_refusal(spec, s));
    auto sim = clothbench::make_engine(spec, s);
    const Matrix3X x0 = grid_positions(s.cloth);
    double worst = 0;
    for (int i = 0; i < 1000; ++i) {
      sim->step(spec.dt);
      for (int p : h.particles)
        worst = std::max(
            worst,
            (sim->positions().col(p) - x0.col(p) - h.motion.displacement(sim->time())).norm());
    }
    INFO("worst handle error " << worst << " m");
    CHECK(worst <= kHandleBullet);
  }
  SECTION("wind") {
    Scene s = flat_cloth(0.0);
    s.cloth.air_drag = 0.05;
    s.wind = {3.0, 1.0, -2.0};
    REQUIRE_FALSE(clothbench::engine_refusal(spec, s));
    auto sim = clothbench::make_engine(spec, s);
    for (int i = 0; i < 6000; ++i) sim->step(spec.dt);
    const Vector3 terminal = s.wind + (1.0 / 81.0) * s.gravity / s.cloth.air_drag;
    const Vector3 v = sim->velocities().rowwise().mean();
    INFO("v = " << v.transpose() << ", expected " << terminal.transpose());
    CHECK((v - terminal).norm() < kTerminalRelative * terminal.norm());
  }
}

TEST_CASE("bullet-deformable: Coulomb friction on an incline, on both sides of tan(theta)",
          "[colliders][bullet]") {
  // Bullet's soft-rigid friction is kDF (1) times the collider's: the deformable world bounds
  // the tangential impulse by it, as Coulomb does. (The classic soft body does not: README.)
  const double theta = 20.0 * M_PI / 180.0;
  clothbench::EngineSpec spec;
  spec.kind = clothbench::EngineKind::bullet_deformable;
  spec.dt = 1e-3;
  for (const double mu : {std::tan(theta) + 0.02, 0.2}) {
    Scene s = flat_cloth(0.01);
    s.gravity = {kG * std::sin(theta), -kG * std::cos(theta), 0.0};
    s.shapes.planes.push_back(floor_plane(mu));
    REQUIRE_FALSE(clothbench::engine_refusal(spec, s));
    auto sim = clothbench::make_engine(spec, s);
    const double start = sim->positions().row(0).mean();
    for (int i = 0; i < 1000; ++i) sim->step(spec.dt);
    const double moved = sim->positions().row(0).mean() - start;
    INFO("mu = " << mu << ": moved " << moved << " m");
    if (mu > std::tan(theta)) {
      CHECK(std::abs(moved) < kStickDistance);
    } else {
      const double a = kG * (std::sin(theta) - mu * std::cos(theta));
      CHECK(std::abs(2.0 * moved - a) < kSlideRelative * a);
    }
  }
}
