#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "cloth/contact/contact_barrier.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "test_scenes.hpp"
#include "tolerances.hpp"

using namespace cloth;

// a named namespace (qualified below): the unity group's other files declare names of their own
namespace collider_work_test {

constexpr double kG = 9.8;             // m/s^2
constexpr double kSpeed = 0.5;         // m/s, the moving colliders'
constexpr double kSymplecticH = 1e-3;  // s
constexpr double kImplicitH = 0.01;    // s

/// A contact path of the custom engine.
enum class Path { after_step, in_solve, barrier };

/// Its name, for the test's messages.
std::string path_name(Path p) {
  switch (p) {
    case Path::after_step:
      return "symplectic Euler, contact pass after the step";
    case Path::in_solve:
      return "implicit Euler, contacts in the solve";
    case Path::barrier:
      return "implicit Euler, barrier";
  }
  return "";
}

/// The engine's options on path p.
SolverOptions options(Path p) {
  if (p == Path::after_step) {
    SolverOptions o;
    o.integrator = Integrator::symplectic_euler;
    return o;
  }
  SolverOptions o = line_search_options(LinearSolver::block_jacobi_cg);
  o.contacts = p == Path::barrier ? ContactMode::barrier : ContactMode::in_solve;
  // tight, so that little momentum is left unexplained by the forces (residual_momentum)
  o.newton_tolerance = 1e-9;
  o.newton_iterations = 100;
  return o;
}

/// The step the tests take on path p (s).
double step_of(Path p) {
  return p == Path::after_step ? kSymplecticH : kImplicitH;
}

/// The 8 x 8 cloth at rest on a floor moving at velocity u with friction mu.
Scene cloth_on_moving_floor(const Vector3& u, double mu) {
  return clothbench::test::cloth_on_floor(kG, u, mu);
}

using clothbench::test::mechanical_energy;

/// The cloth's momentum (kg m/s).
Vector3 momentum(const MassSpringCloth& c) {
  return c.velocities() * c.model().mass;
}

/// What the last step's solve left of its residual, as momentum (kg m/s): the cloth's mass
/// times the largest |M^-1 residual|, a bound on each component of the momentum that the
/// forces do not explain (0 without a Newton solve).
double residual_momentum(const MassSpringCloth& c) {
  return c.newton() ? c.model().mass.sum() * c.newton()->last_residual() : 0.0;
}

/// What a run of steps showed: the largest contact_work of a step (J) and the momentum the
/// solves' residuals left unexplained, summed over the steps (kg m/s, residual_momentum).
struct RunBooks {
  double largest_contact_work = -1.0;
  double unexplained = 0.0;
};

/// Takes steps of h seconds and keeps their books.
RunBooks run_steps(MassSpringCloth& c, double h, int steps) {
  RunBooks b;
  for (int step = 0; step < steps; ++step) {
    c.step(h);
    b.largest_contact_work = std::max(b.largest_contact_work, c.contact_work());
    b.unexplained += residual_momentum(c);
  }
  return b;
}

}  // namespace collider_work_test

namespace cwt = collider_work_test;
namespace tol = clothbench::tol;

TEST_CASE("a static collider does no collider work, whatever the contact path",
          "[collision][collider-work][slow]") {
  const cwt::Path path = GENERATE(cwt::Path::after_step, cwt::Path::in_solve, cwt::Path::barrier);
  CAPTURE(cwt::path_name(path));
  // a cloth held at two corners falls onto a sphere and drapes onto a floor below it; contacts
  // in the solve are only for colliders without friction
  Scene s = clothbench::test::small_cloth(8, 200.0, 0.5);
  s.cloth.center = {0.0, 0.45, 0.0};
  const double mu = path == cwt::Path::in_solve ? 0.0 : 0.4;
  Sphere sphere;
  sphere.center = {0.2, 0.1, 0.1};
  sphere.radius = 0.3;
  sphere.friction = mu;
  s.spheres.push_back(sphere);
  HalfSpace floor;
  floor.point = {0.0, -0.3, 0.0};
  floor.friction = mu;
  s.shapes.planes.push_back(floor);
  s.gravity = {0.0, -cwt::kG, 0.0};
  MassSpringCloth c(s, cwt::options(path));
  const double h = cwt::step_of(path);
  int steps_in_contact = 0;
  for (int step = 0; step < static_cast<int>(std::lround(1.5 / h)); ++step) {
    c.step(h);
    if (c.contacts() > 0) ++steps_in_contact;
    // exactly: each contact's impulse times a zero velocity
    REQUIRE(c.collider_work() == 0.0);
  }
  // it did touch both, and the contacts did work
  CHECK(steps_in_contact > 10);
  CHECK(c.positions().row(1).minCoeff() < floor.point.y() + 2 * floor.margin);
  CHECK(c.contact_work() != 0.0);
}

TEST_CASE("a rising floor under a resting cloth, symplectic Euler: the books by hand",
          "[collision][collider-work]") {
  // every particle alike, so by hand for one of mass m, on the shell at rest: the first step
  // falls g h^2 into the floor, which rose V h; the pass puts it back on the shell, gives it
  // the floor's velocity V and takes impulse m (V + g h) . V from the floor's motion, and its
  // energy change leaves -m V^2 / 2 + m g^2 h^2 / 2 relative to the floor (the catch is
  // inelastic). Every later step the particle sinks g h^2 relative to the floor and is put back
  // with impulse m g h: the floor does m g h V, and the projection gives back the m g^2 h^2 / 2
  // the step lost falling into the floor (energy_error books that loss, -m g^2 h^2 / 2)
  const double mass_total = 6.4, v = cwt::kSpeed, g = cwt::kG, h = cwt::kSymplecticH;
  MassSpringCloth c(cwt::cloth_on_moving_floor({0.0, v, 0.0}, 0.3),
                    cwt::options(cwt::Path::after_step));
  REQUIRE(c.model().mass.sum() == Approx(mass_total).epsilon(tol::kColliderWorkRoundoff));
  const double e0 = cwt::mechanical_energy(c);
  const int steps = 1000;
  for (int step = 0; step < steps; ++step) c.step(h);
  const double n = steps;
  CHECK(c.collider_work() ==
        Approx(mass_total * v * (v + g * n * h)).epsilon(tol::kColliderWorkRoundoff));
  CHECK(c.contact_work() == Approx(mass_total * (0.5 * n * g * g * h * h - 0.5 * v * v))
                                .epsilon(tol::kColliderWorkRoundoff));
  CHECK(c.velocities().row(1).mean() == Approx(v).epsilon(tol::kColliderWorkRoundoff));
  // the cloth gained about what the floor gave: all but the catch's v^2 / 2 (2.4 % here)
  const double gained = cwt::mechanical_energy(c) + c.dissipated() - e0;
  CHECK(gained ==
        Approx(mass_total * (0.5 * v * v + g * v * n * h)).epsilon(tol::kColliderWorkRoundoff));
  CHECK(gained < c.collider_work());
  CHECK(gained > 0.97 * c.collider_work());
}

TEST_CASE("a floor sliding under a resting cloth, symplectic Euler: friction's books by hand",
          "[collision][collider-work]") {
  // every particle alike: friction accelerates it at mu g along the floor until it moves with
  // it, so the floor does M U^2 (its impulse M U times U) and the cloth keeps M U^2 / 2: friction
  // relative to the floor took M U^2 / 2; along the normal the pass gives back m g^2 h^2 / 2 a
  // step as on a floor at rest (the floor's motion is tangential: no normal work of its own)
  const double mass_total = 6.4, u = cwt::kSpeed, g = cwt::kG, h = cwt::kSymplecticH;
  MassSpringCloth c(cwt::cloth_on_moving_floor({u, 0.0, 0.0}, 0.5),
                    cwt::options(cwt::Path::after_step));
  const int steps = 500;  // the cloth catches up after u / (mu g) = 0.1 s
  double largest_collider_step = 0.0;
  for (int step = 0; step < steps; ++step) {
    const double before = c.collider_work();
    c.step(h);
    largest_collider_step = std::max(largest_collider_step, c.collider_work() - before);
    CHECK(c.collider_work() >= before);  // the floor only ever drags the cloth along
  }
  const double n = steps;
  CHECK(c.velocities().row(0).mean() == Approx(u).epsilon(tol::kColliderWorkRoundoff));
  CHECK(c.collider_work() == Approx(mass_total * u * u).epsilon(tol::kColliderWorkRoundoff));
  CHECK(c.contact_work() == Approx(mass_total * (0.5 * n * g * g * h * h - 0.5 * u * u))
                                .epsilon(tol::kColliderWorkRoundoff));
  // the floor's work is its velocity times the momentum it gave (its impulse along x)
  CHECK(c.collider_work() == Approx(u * cwt::momentum(c).x()).epsilon(tol::kColliderWorkRoundoff));
  CHECK(largest_collider_step > 0.0);
}

TEST_CASE("a rising floor under a resting cloth, implicit Euler: the floor supplies the lift",
          "[collision][collider-work][barrier]") {
  const cwt::Path path = GENERATE(cwt::Path::in_solve, cwt::Path::barrier);
  CAPTURE(cwt::path_name(path));
  const double v = cwt::kSpeed, g = cwt::kG, h = cwt::kImplicitH;
  // frictionless, so that the solve holds the contacts in in-solve mode
  MassSpringCloth c(cwt::cloth_on_moving_floor({0.0, v, 0.0}, 0.0), cwt::options(path));
  const double mass_total = c.model().mass.sum();
  const double e0 = cwt::mechanical_energy(c);
  const int steps = 100;
  const auto [largest_contact_work, unexplained] = cwt::run_steps(c, h, steps);
  const double t = steps * h;
  CAPTURE(c.collider_work(), c.contact_work(), largest_contact_work, unexplained);
  // the floor's impulse is the momentum change less gravity's, and its work that impulse
  // times V, but for what the solves' residuals leave unexplained
  const double impulse = cwt::momentum(c).y() + mass_total * g * t;
  CHECK(std::abs(c.collider_work() - v * impulse) <=
        v * unexplained + tol::kColliderWorkRoundoff * c.collider_work());
  CHECK(c.collider_work() > mass_total * g * v * t);
  // relative to the floor the contact never gains: the in-solve constraint holds the normal
  // velocity at the floor's (nothing relative to it), the barrier is a convex potential of
  // the distance to the floor that starts at zero (its relative work is at most minus it)
  const double roundoff = tol::kContactWorkSign * c.collider_work();
  CHECK(largest_contact_work <= roundoff);
  // what the cloth gained, and the dampers took, is what the floor did but for the catch's
  // loss and implicit Euler's own dissipation
  const double gained = cwt::mechanical_energy(c) + c.dissipated() - e0;
  CHECK(gained <= c.collider_work() + roundoff);
  CHECK(gained > 0.95 * c.collider_work());
}

TEST_CASE("a floor sliding under a resting cloth, barrier: friction drags it along",
          "[collision][collider-work][barrier]") {
  const double u = cwt::kSpeed, h = cwt::kImplicitH;
  MassSpringCloth c(cwt::cloth_on_moving_floor({u, 0.0, 0.0}, 0.5),
                    cwt::options(cwt::Path::barrier));
  const int steps = 100;
  const auto [largest_contact_work, unexplained] = cwt::run_steps(c, h, steps);
  CAPTURE(c.collider_work(), c.contact_work(), largest_contact_work, unexplained);
  const double mass_total = c.model().mass.sum();
  // it moves with the floor (the lagged friction holds it as a stiff spring below a sliding
  // speed of kFrictionSpeed), whose friction did its impulse (the momentum along x) times U
  CHECK(c.velocities().row(0).mean() == Approx(u).margin(kFrictionSpeed));
  CHECK(std::abs(c.collider_work() - u * cwt::momentum(c).x()) <=
        u * unexplained + tol::kColliderWorkRoundoff * c.collider_work());
  CHECK(c.collider_work() == Approx(mass_total * u * u).margin(mass_total * u * kFrictionSpeed));
  // friction relative to the floor only ever takes, and the barrier starts at zero
  CHECK(largest_contact_work <= tol::kContactWorkSign * c.collider_work());
  CHECK(c.contact_work() < -0.4 * mass_total * u * u);
}

TEST_CASE("a sphere rising into a cloth at rest, without gravity: its motion does the work",
          "[collision][collider-work][barrier]") {
  const cwt::Path path = GENERATE(cwt::Path::after_step, cwt::Path::barrier);
  CAPTURE(cwt::path_name(path));
  // a free cloth at rest in the plane y = 0; a frictionless sphere of radius 0.3 m 5 cm below
  // it rises at V through 0.6 m in 1.2 s
  Scene s = clothbench::test::small_cloth(8, 200.0, 0.5);
  s.held.clear();
  s.gravity.setZero();
  Sphere sphere;
  sphere.center = {0.05, -0.35 - sphere.margin, 0.0};
  sphere.radius = 0.3;
  sphere.velocity = {0.0, cwt::kSpeed, 0.0};
  s.spheres.push_back(sphere);
  MassSpringCloth c(s, cwt::options(path));
  const double h = cwt::step_of(path);
  const double e0 = cwt::mechanical_energy(c);
  const auto [largest_contact_work, unexplained] =
      cwt::run_steps(c, h, static_cast<int>(std::lround(1.2 / h)));
  const double gained = cwt::mechanical_energy(c) + c.dissipated() - e0;
  CAPTURE(c.collider_work(), c.contact_work(), largest_contact_work, gained, unexplained);
  // without gravity the sphere's impulse is the cloth's momentum, and its work that times V
  // (but for what the solves' residuals leave unexplained)
  CHECK(std::abs(c.collider_work() - cwt::kSpeed * cwt::momentum(c).y()) <=
        cwt::kSpeed * unexplained + tol::kColliderWorkRoundoff * c.collider_work());
  CHECK(c.collider_work() > 0.0);
  // relative to the sphere the contacts only take (the catches are inelastic); the pass after
  // the step has one positive term of its own, F^2 h^2 / (2 m) a step for a particle it holds
  // against a load F (the rising floor's test above), which at this step never makes up what
  // the catches took
  CHECK(largest_contact_work <= tol::kContactWorkSign * c.collider_work());
  CHECK(gained <= c.collider_work());
}
