#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "cloth/contact/sphere_collision.hpp"
#include "cloth/forces/energies.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "tolerances.hpp"

using namespace cloth;
namespace tol = clothbench::tol;

namespace {

// loose particles (no springs) above the unit sphere
Scene dust(int nu, int nv, double size, double height, double restitution) {
  Scene s;
  s.cloth.nu = nu;
  s.cloth.nv = nv;
  s.cloth.size_u = size;
  s.cloth.size_v = size;
  s.cloth.center = {0.0, height, 0.0};
  s.cloth.k_structural = s.cloth.k_shear = s.cloth.k_bend = 0.0;
  Sphere sphere;
  sphere.restitution = restitution;
  s.spheres.push_back(sphere);
  return s;
}

}  // namespace

TEST_CASE("no particle ends a step inside a sphere", "[collision]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  const Scene s = dust(7, 7, 1.2, 1.5, 0.0);
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth c(s, o);
  const double shell = 1.0 + s.spheres[0].margin;
  int touching = 0;
  for (int i = 0; i < 1500; ++i) {
    c.step(1e-3);
    for (Eigen::Index p = 0; p < c.positions().cols(); ++p) {
      const double r = c.positions().col(p).norm();
      REQUIRE(r >= shell - tol::kContactShell);
      if (r < shell + tol::kContactShell) ++touching;
    }
  }
  INFO(integrator_name(integrator));
  CHECK(touching > 1000);  // the particles did land and slide
}

TEST_CASE("with C_R = 0 nothing bounces off, with C_R = 0.5 it does", "[collision]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  const double restitution = GENERATE(0.0, 0.5);
  // loose particles dropped 0.5 m onto the top of the sphere
  const Scene s = dust(3, 3, 0.4, 1.5, restitution);
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth c(s, o);
  const Eigen::Index n = c.positions().cols();
  const double shell = 1.0 + s.spheres[0].margin;
  std::vector<double> contact_y(static_cast<size_t>(n), -1.0);
  double largest_rise = 0.0;
  for (int i = 0; i < 1000; ++i) {
    c.step(1e-3);
    for (Eigen::Index p = 0; p < n; ++p) {
      const double y = c.positions()(1, p);
      double& first = contact_y[static_cast<size_t>(p)];
      if (first < 0 && c.positions().col(p).norm() < shell + tol::kContactShell) first = y;
      if (first >= 0) largest_rise = std::max(largest_rise, y - first);
    }
  }
  INFO(integrator_name(integrator)
       << " C_R " << restitution << ": largest rise after contact " << largest_rise << " m");
  for (double y : contact_y) REQUIRE(y > 0);  // every particle landed
  if (restitution == 0.0)
    CHECK(largest_rise <= tol::kContactShell);
  else
    CHECK(largest_rise > 0.05);  // a C_R = 0.5 bounce from 3 m/s rises about 0.11 m
}

TEST_CASE("restitution reverses the normal velocity by C_R", "[collision]") {
  // two particles 1 mm apart dropped onto the top of the sphere
  const Scene s = dust(2, 1, 0.001, 1.5, 0.5);
  SolverOptions o;
  o.integrator = Integrator::symplectic_euler;
  MassSpringCloth c(s, o);
  const double h = 1e-3;
  for (int i = 0; i < 2000; ++i) {
    const double vy_before = c.velocities()(1, 0);
    c.step(h);
    if (c.velocities()(1, 0) > 0) {
      // symplectic Euler arrived with vy_before - g h, the sphere returned half of it
      CHECK(c.velocities()(1, 0) == Approx(-0.5 * (vy_before - 9.8 * h)).epsilon(1e-6));
      return;
    }
  }
  FAIL("the particles never bounced");
}

TEST_CASE("contact law: restitution, friction and a moving sphere", "[collision]") {
  Sphere s;
  s.center = {0.0, 0.0, 0.0};
  s.radius = 1.0;
  s.margin = 0.0;
  s.restitution = 0.25;
  s.friction = 0.5;
  s.velocity = {0.0, 0.2, 0.0};
  Matrix3X x(3, 2), v(3, 2);
  x.col(0) = Vector3(0.0, 0.9, 0.0);  // inside, at t = 0
  x.col(1) = Vector3(0.0, 3.0, 0.0);  // far away
  v.col(0) = Vector3(1.0, -2.0, 0.0);
  v.col(1) = Vector3(1.0, -2.0, 0.0);
  const VectorX mass = VectorX::Constant(2, 2.0);
  const Matrix3X free = Matrix3X::Ones(3, 2);
  const double removed = resolve_sphere_contacts({s}, 0.0, x, v, mass, free);
  // moved to the surface; relative normal speed -2.2 becomes +0.55, the normal impulse is
  // 1.25 * 2.2 = 2.75 m/s and friction takes 0.5 * 2.75 of the 1 m/s slip: all of it
  CHECK(x.col(0).isApprox(Vector3(0.0, 1.0, 0.0)));
  CHECK(v(1, 0) == Approx(0.2 + 0.55));
  CHECK(v(0, 0) == Approx(0.0).margin(1e-15));
  CHECK(x.col(1) == Vector3(0.0, 3.0, 0.0));
  CHECK(v.col(1) == Vector3(1.0, -2.0, 0.0));
  CHECK(removed == Approx(0.5 * 2.0 * (5.0 - 0.75 * 0.75)));
  // a weaker friction only slows the slip
  s.friction = 0.1;
  x.col(0) = Vector3(0.0, 0.9, 0.0);
  v.col(0) = Vector3(1.0, -2.0, 0.0);
  resolve_sphere_contacts({s}, 0.0, x, v, mass, free);
  CHECK(v(0, 0) == Approx(1.0 - 0.1 * 2.75));
  // a held axis is never moved by contact
  Matrix3X held = free;
  held(1, 0) = 0.0;
  x.col(0) = Vector3(0.0, 0.9, 0.0);
  v.col(0) = Vector3(0.0, 0.0, 0.0);
  resolve_sphere_contacts({s}, 0.0, x, v, mass, held);
  CHECK(x(1, 0) == 0.9);
}

TEST_CASE("a scene without spheres pays nothing for collision", "[collision]") {
  // the step of a sphere-less scene and of the same scene with a far sphere give the same
  // state, and the sphere-less one skips the contact pass entirely (no sphere to loop over)
  Scene s = dust(3, 3, 1.0, 5.0, 0.0);
  s.cloth.k_structural = 100.0;
  Scene bare = s;
  bare.spheres.clear();
  SolverOptions o;
  MassSpringCloth a(s, o), b(bare, o);
  for (int i = 0; i < 100; ++i) {
    a.step(1e-3);
    b.step(1e-3);
  }
  CHECK(a.positions() == b.positions());
  // cost in distance tests, not seconds: every particle against the sphere, or nothing at all
  CHECK(a.counters().contact_tests == 100 * 9);
  CHECK(b.counters().contact_tests == 0);
}

TEST_CASE("contact work is booked exactly when a particle is pushed out of a sphere",
          "[collision]") {
  // One particle 5 mm inside the unit sphere's contact shell on the pole, moving in at
  // 0.3 m/s; its partner far away. A symplectic Euler step moves it further in, the projection
  // lifts it back onto the shell against gravity (work m g lift) and cancels the normal
  // velocity (work -1/2 m v^2): no springs, so that is all the contact does.
  const Scene s = dust(2, 1, 1.0, 1.5, 0.0);
  SolverOptions o;
  o.integrator = Integrator::symplectic_euler;
  MassSpringCloth c(s, o);
  const double shell = 1.0 + s.spheres[0].margin, h = 1e-3, g = 9.8, m = 1.0, u = 0.3;
  Matrix3X x = c.positions(), v = Matrix3X::Zero(3, 2);
  x.col(0) = Vector3(0.0, shell - 0.005, 0.0);
  x.col(1) = Vector3(5.0, 5.0, 0.0);
  v(1, 0) = -u;
  c.set_state(x, v);
  c.step(h);
  const double v_in = u + g * h;                // speed into the sphere after the step
  const double lift = 0.005 + h * v_in;         // back onto the shell
  const double expected = m * g * lift - 0.5 * m * v_in * v_in;
  CHECK(c.positions()(1, 0) == Approx(shell).epsilon(1e-15));
  CHECK(c.velocities()(1, 0) == 0.0);
  CHECK(c.contact_work() == Approx(expected).epsilon(1e-12));
  CHECK(c.dissipated() == 0.0);  // no damper, no drag: the contact is not dissipation
}

TEST_CASE("with the contact work booked, rk4's energy books close on a sphere", "[collision]") {
  // Loose particles land and slide on the sphere. Between contacts each one falls freely,
  // which rk4 integrates exactly, so E - W_contact stays E_0 to round-off although the
  // contact work itself (projection lifts, normal velocity cancelled) is not small.
  const Scene s = dust(5, 5, 1.2, 1.3, 0.0);
  SolverOptions o;
  o.integrator = Integrator::rk4;
  MassSpringCloth c(s, o);
  const Model& m = c.model();
  const double e0 = compute_energies(m, c.positions(), c.velocities()).total();
  double worst = 0.0;
  for (int i = 0; i < 2000; ++i) {
    c.step(1e-3);
    const double e = compute_energies(m, c.positions(), c.velocities()).total();
    worst = std::max(worst, std::abs(e + c.dissipated() - c.contact_work() - e0));
  }
  INFO("contact work " << c.contact_work() << " J, largest error " << worst << " J");
  CHECK(std::abs(c.contact_work()) > 1.0);
  CHECK(worst < 1e-9 * std::abs(e0));
}
