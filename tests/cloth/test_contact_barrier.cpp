#include <catch2/catch.hpp>
#include <cmath>

#include "cloth/contact/colliders.hpp"
#include "cloth/contact/contact_barrier.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "harness/scenario/engine_refusal.hpp"
#include "test_scenes.hpp"

using namespace cloth;

namespace {

constexpr double kFrame = 1.0 / 30.0;  // s, the large step
constexpr double kG = 9.8;             // m/s^2

/// The large-step fabric scene at n per side: a 1 m square of 0.2 kg, springs 500 / 500 / 5
/// N/m, held along its edge i = 0, swinging down from the horizontal onto a fixed frictionless
/// sphere whose top is 0.2 m below it (examples/large_steps/fabric_128.toml at n per side).
Scene swing_onto_sphere(int n) {
  Scene s = clothbench::test::small_cloth(n, 500.0, 0.01);
  s.cloth.k_bend = 5.0;
  s.cloth.center = {0.0, 0.8, 0.0};
  s.cloth.particle_mass = 0.2 / (n * n);
  s.held.assign(static_cast<size_t>(n * n), 0);
  for (int j = 0; j < n; ++j) s.held[static_cast<size_t>(particle_index(s.cloth, 0, j))] = kHoldAll;
  Sphere sphere;
  sphere.center = {0.0, 0.3, 0.0};
  sphere.radius = 0.3;
  sphere.margin = 0.005;
  s.spheres.push_back(sphere);
  s.gravity = {0.0, -kG, 0.0};
  return s;
}

SolverOptions barrier_options() {
  SolverOptions o = line_search_options(LinearSolver::block_jacobi_cg);
  o.contacts = ContactMode::barrier;
  return o;
}

using clothbench::test::mechanical_energy;

}  // namespace

TEST_CASE("the barrier's slope and curvature are its derivatives, and it is C2 at dhat",
          "[barrier]") {
  constexpr double kHat = 0.005;  // m
  constexpr double kStep = 1e-9;  // m, central differences: error ~ kStep^2 b''' (~1e-10 here)
  for (const double s : {0.01, 0.1, 0.3, 0.5, 0.8, 0.99}) {
    const double d = s * kHat;
    const double slope = (barrier(d + kStep, kHat) - barrier(d - kStep, kHat)) / (2 * kStep);
    const double curve =
        (barrier_slope(d + kStep, kHat) - barrier_slope(d - kStep, kHat)) / (2 * kStep);
    CAPTURE(s);
    CHECK(barrier_slope(d, kHat) == Approx(slope).epsilon(1e-6).margin(1e-12));
    CHECK(barrier_curvature(d, kHat) == Approx(curve).epsilon(1e-6).margin(1e-9));
    // pushes out, convex
    CHECK(barrier_slope(d, kHat) < 0.0);
    CHECK(barrier_curvature(d, kHat) > 0.0);
  }
  // value, slope and curvature all vanish at the layer's top and stay zero above it
  CHECK(barrier(kHat * (1 - 1e-6), kHat) == Approx(0.0).margin(1e-15));
  CHECK(barrier_slope(kHat * (1 - 1e-6), kHat) == Approx(0.0).margin(1e-12));
  CHECK(barrier_curvature(kHat * (1 - 1e-6), kHat) == Approx(0.0).margin(1e-5));
  CHECK(barrier(2 * kHat, kHat) == 0.0);
  CHECK(std::isinf(barrier(0.0, kHat)));
  CHECK(std::isinf(barrier(-kHat, kHat)));
}

TEST_CASE("the barrier's contact forces are minus the gradient of its energy", "[barrier]") {
  // three particles near a sphere and a tilted plane, one near both
  Scene s = clothbench::test::small_cloth(2, 10.0, 0.0);
  s.held.clear();
  Sphere sphere;
  sphere.radius = 0.5;
  sphere.margin = 0.02;
  s.spheres.push_back(sphere);
  Matrix3X x(3, 4);
  x.col(0) = Vector3(0.3, 0.4, 0.05).normalized() * 0.51;
  x.col(1) = Vector3(-0.2, -1.0, 0.1).normalized() * 0.507;
  x.col(2) = Vector3(0.0, 0.2, 1.0).normalized() * 0.519;
  x.col(3) = Vector3(2.0, 2.0, 2.0);  // far from both
  // a plane 12 mm under particle 1, tilted
  HalfSpace plane;
  plane.normal = Vector3(0.2, 1.0, 0.1).normalized();
  plane.point = x.col(1) - 0.012 * plane.normal;
  plane.margin = 0.03;
  s.shapes.planes.push_back(plane);
  const Model m = build_model(s);
  const ColliderBarrier b(m);
  std::vector<BarrierContact> contacts;
  b.contacts(m, 0.0, x, contacts);
  REQUIRE(contacts.size() == 4);  // particle 1 is within both layers
  Matrix3X f = Matrix3X::Zero(3, 4);
  ColliderBarrier::add_forces(contacts, f);
  constexpr double kStep = 1e-8;  // m
  for (int p = 0; p < 4; ++p)
    for (int r = 0; r < 3; ++r) {
      Matrix3X xp = x, xm = x;
      xp(r, p) += kStep;
      xm(r, p) -= kStep;
      const double gradient = (b.energy(m, 0.0, xp) - b.energy(m, 0.0, xm)) / (2 * kStep);
      CAPTURE(p, r);
      CHECK(-gradient == Approx(f(r, p)).epsilon(1e-6).margin(1e-9));
    }
  // on a plane the Hessian is exactly kappa b'' n n^T: the normal-normal second difference
  const BarrierContact& on_plane = contacts.back();
  REQUIRE(on_plane.particle == 1);
  Matrix3X xp = x, xm = x;
  xp.col(1) += kStep * plane.normal;
  xm.col(1) -= kStep * plane.normal;
  // the sphere's share along the plane's normal is removed by differencing its force alone
  std::vector<BarrierContact> cp, cm;
  b.contacts(m, 0.0, xp, cp);
  b.contacts(m, 0.0, xm, cm);
  const double dforce = (cp.back().force - cm.back().force) / (2 * kStep);
  CHECK(-dforce == Approx(on_plane.stiffness).epsilon(1e-5));
}

TEST_CASE("a particle resting on a floor with a barrier sits where the barrier holds its weight",
          "[barrier][integrator]") {
  // one free particle of 0.01 kg above a frictionless floor, implicit Euler at 1/30 s
  Scene s = clothbench::test::one_spring(0.01, 0.0, 0.0);
  s.held.clear();
  s.cloth.k_structural = 0.0;
  HalfSpace floor;
  floor.margin = 0.01;
  s.shapes.planes.push_back(floor);
  s.gravity = {0.0, -kG, 0.0};
  SolverOptions o = barrier_options();
  o.newton_tolerance = 1e-12;
  MassSpringCloth c(s, o);
  Matrix3X x = c.positions();
  x.row(1).setConstant(0.05);  // m, above the layer
  c.set_state(x, Matrix3X::Zero(3, 2));
  for (int i = 0; i < 300; ++i) c.step(kFrame);
  // the height where kappa |b'(d)| = m g, found by bisection on the formula (an independent
  // route: the engine minimises the step's potential with Newton)
  const double hat = floor.margin;
  double lo = 1e-9, hi = hat;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double force = -kBarrierAcceleration / hat * barrier_slope(mid, hat);  // per kg
    (force > kG ? lo : hi) = mid;
  }
  CHECK(c.positions().row(1).minCoeff() == Approx(lo).epsilon(1e-6));
  CHECK(c.positions().row(1).maxCoeff() == Approx(lo).epsilon(1e-6));
  // the floor's impulse over the last step is the weight times the step
  CHECK(c.newton()->contact_impulse().y() == Approx(2 * 0.01 * kG * kFrame).epsilon(1e-6));
  CHECK(c.contacts() == 2);
}

TEST_CASE("a fabric swinging onto a sphere at 1/30 s: the barrier never gives energy",
          "[barrier][integrator]") {
  // 16 per side, 3 s: the cloth lands on the sphere, slides off its side and swings under it
  const Scene s = swing_onto_sphere(16);
  MassSpringCloth c(s, barrier_options());
  const double e0 = mechanical_energy(c);
  const Sphere& sphere = s.spheres[0];
  double largest_rise = -1.0, largest_work = -1.0, nearest = 1.0;
  int steps_in_contact = 0;
  for (int step = 0; step < 90; ++step) {
    c.step(kFrame);
    largest_rise = std::max(largest_rise, mechanical_energy(c) - e0);
    largest_work = std::max(largest_work, c.contact_work());
    for (Eigen::Index p = 0; p < c.positions().cols(); ++p)
      nearest = std::min(nearest, (c.positions().col(p) - sphere.center).norm() - sphere.radius);
    if (c.contacts() > 0) ++steps_in_contact;
  }
  CAPTURE(e0, largest_rise, largest_work, nearest, steps_in_contact);
  // it did meet the sphere, and stayed outside it
  CHECK(steps_in_contact >= 5);
  CHECK(nearest > 0.0);
  // the static sphere's work, summed from the start, is never positive, and the energy
  // never rises above the start (round-off of the 0.2 kg cloth's energy: 1e-12 J)
  CHECK(largest_work <= 1e-12);
  CHECK(largest_rise <= 1e-12);
}

TEST_CASE("a cloth on a rising floor is carried by the barrier", "[barrier][integrator]") {
  Scene s = clothbench::test::small_cloth(8, 200.0, 0.5);
  s.held.clear();
  HalfSpace floor;
  floor.velocity = {0.0, 0.5, 0.0};  // m/s
  s.cloth.center = {0.0, floor.margin, 0.0};
  s.shapes.planes.push_back(floor);
  s.gravity = {0.0, -kG, 0.0};
  MassSpringCloth c(s, barrier_options());
  for (int step = 0; step < 30; ++step) c.step(kFrame);
  // above the floor, within its layer, moving with it
  const double floor_y = 0.5 * c.time();
  CHECK(c.positions().row(1).minCoeff() > floor_y);
  CHECK(c.positions().row(1).maxCoeff() < floor_y + floor.margin);
  CHECK(c.velocities().row(1).mean() == Approx(0.5).epsilon(1e-3));
}

TEST_CASE("contacts = barrier refuses a collider that bounces", "[barrier]") {
  clothbench::EngineSpec spec;
  spec.kind = clothbench::EngineKind::custom;
  spec.solver = barrier_options();
  Scene s = swing_onto_sphere(4);
  s.spheres[0].friction = 0.3;  // friction is in the barrier's potential
  CHECK_FALSE(clothbench::engine_refusal(spec, s));
  s.spheres[0].restitution = 0.5;
  const auto refusal = clothbench::engine_refusal(spec, s);
  REQUIRE(refusal);
  CHECK_THAT(refusal->why, Catch::Contains("sphere.0 has restitution 0.5"));
  // the other modes take it
  spec.solver.contacts = ContactMode::in_solve;
  CHECK_FALSE(clothbench::engine_refusal(spec, s));
}

TEST_CASE("the lagged friction's force and Hessian are its potential's derivatives", "[barrier]") {
  constexpr double kH = 0.01;  // s
  const double eps = kFrictionSpeed * kH;
  FrictionContact c;
  c.particle = 1;
  c.normal = Vector3(0.1, 1.0, -0.2).normalized();
  c.collider_velocity = {0.02, 0.0, 0.01};
  c.bound = 0.7;
  StepFriction f;
  f.start({c}, kH);
  // sliding below, near and above the smoothing length eps
  for (const double speed : {0.2, 0.9, 1.5, 40.0}) {
    Matrix3X v = Matrix3X::Zero(3, 2);
    v.col(1) = c.collider_velocity + speed * kFrictionSpeed * Vector3(0.6, 0.3, 0.8).normalized();
    Matrix3X force = Matrix3X::Zero(3, 2);
    f.add_forces(v, force);
    std::vector<int> particles;
    std::vector<Matrix3> blocks;
    f.add_blocks(v, 1.0, particles, blocks);
    REQUIRE(particles == std::vector<int>{1});
    const double step = 1e-4 * kFrictionSpeed;  // m/s
    for (int r = 0; r < 3; ++r) {
      Matrix3X vp = v, vm = v;
      vp(r, 1) += step;
      vm(r, 1) -= step;
      // d/dv = h d/dx
      const double gradient = (f.energy(vp) - f.energy(vm)) / (2 * step * kH);
      Matrix3X fp = Matrix3X::Zero(3, 2), fm = Matrix3X::Zero(3, 2);
      f.add_forces(vp, fp);
      f.add_forces(vm, fm);
      const Vector3 column = -(fp.col(1) - fm.col(1)) / (2 * step * kH);
      CAPTURE(speed, r);
      CHECK(-gradient == Approx(force(r, 1)).epsilon(1e-5).margin(1e-9));
      for (int q = 0; q < 3; ++q)
        CHECK(blocks[0](q, r) == Approx(column[q]).epsilon(1e-4).margin(1e-6 * c.bound / eps));
    }
    // Coulomb: never more than mu lambda, and opposite the sliding
    CHECK(force.col(1).norm() <= c.bound * (1 + 1e-12));
    CHECK(force.col(1).dot(v.col(1) - c.collider_velocity) < 0.0);
    CHECK(std::abs(force.col(1).dot(c.normal)) <= 1e-12 * c.bound);
  }
}

TEST_CASE(
    "a particle on an incline with barrier friction sticks below tan(theta) = mu and "
    "slides at g (sin - mu cos) above it",
    "[barrier][integrator][friction]") {
  constexpr double kMu = 0.5;
  for (const double tan_theta : {0.4, 0.6}) {
    const double theta = std::atan(tan_theta);
    Scene s = clothbench::test::one_spring(0.01, 0.0, 0.0);
    s.held.clear();
    HalfSpace incline;
    incline.normal = Vector3(-std::sin(theta), std::cos(theta), 0.0);
    incline.friction = kMu;
    s.shapes.planes.push_back(incline);
    s.gravity = {0.0, -kG, 0.0};
    SolverOptions o = barrier_options();
    o.newton_tolerance = 1e-10;
    MassSpringCloth c(s, o);
    // both particles just inside the layer, at rest
    Matrix3X x = c.positions();
    for (int p = 0; p < 2; ++p)
      x.col(p) = Vector3(0.3 * p, 0.0, 0.0) + 0.8 * incline.margin * incline.normal;
    c.set_state(x, Matrix3X::Zero(3, 2));
    constexpr double kStep = 0.01;  // s
    for (int i = 0; i < 100; ++i) c.step(kStep);
    const Vector3 down_slope = Vector3(std::cos(theta), std::sin(theta), 0.0) * -1.0;
    const double v1 = c.velocities().col(0).dot(down_slope);
    c.step(kStep);
    const double v2 = c.velocities().col(0).dot(down_slope);
    CAPTURE(tan_theta, v1, v2);
    if (tan_theta < kMu) {
      // held: creeping slower than the smoothing speed
      CHECK(std::abs(v2) < kFrictionSpeed);
    } else {
      // sliding: backward Euler's velocity gains h a per step exactly for a constant force
      const double a = kG * (std::sin(theta) - kMu * std::cos(theta));
      CHECK((v2 - v1) / kStep == Approx(a).epsilon(1e-6));
      CHECK(v2 == Approx(a * c.time()).epsilon(0.02));
    }
  }
}
