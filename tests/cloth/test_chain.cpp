#include <catch2/catch.hpp>
#include <cmath>

#include "cloth/integrators/mass_spring_cloth.hpp"
#include "test_scenes.hpp"
#include "tolerances.hpp"

using namespace cloth;
namespace tol = clothbench::tol;

TEST_CASE("a hanging chain settles where discrete statics put it", "[integrator][springs]") {
  const Integrator integrator = GENERATE(Integrator::implicit_euler, Integrator::symplectic_euler);
  const int n = 10;
  const double m = 0.1, k = 100.0, l = 0.1, g = 9.8;
  const Scene s = clothbench::test::chain(n, m, k, l, 5.0, g);
  SolverOptions o;
  o.integrator = integrator;
  o.cg_tolerance = 1e-12;
  MassSpringCloth c(s, o);
  const double h = integrator == Integrator::implicit_euler ? 1e-2 : 1e-3;
  for (int i = 0; i < static_cast<int>(30.0 / h); ++i) c.step(h);
  const Matrix3X& x = c.positions();
  INFO(integrator_name(integrator));
  // the spring above particle j carries the j + 1 particles below it: stretch (j + 1) m g / k
  for (int j = 0; j < n; ++j) {
    const double stretch = (x.col(j + 1) - x.col(j)).norm() - l;
    const double expected = (j + 1) * m * g / k;
    CHECK(stretch == Approx(expected).epsilon(tol::kStaticStretchRelative));
  }
}

TEST_CASE("a chain oscillates at its analytic lowest eigenfrequency", "[integrator][springs]") {
  const Integrator integrator = GENERATE(Integrator::rk4, Integrator::symplectic_euler);
  const int n = 10;
  const double m = 0.1, k = 100.0, l = 0.1;
  const Scene s = clothbench::test::chain(n, m, k, l, 0.0, 0.0);
  // fixed at the top, free at the bottom: u_s = sin(s theta), theta = pi / (2n + 1),
  // omega = 2 sqrt(k / m) sin(theta / 2), s counting particles down from the pin
  const double theta = M_PI / (2 * n + 1);
  const double omega = 2.0 * std::sqrt(k / m) * std::sin(theta / 2);
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth c(s, o);
  Matrix3X v = Matrix3X::Zero(3, n + 1);
  for (int j = 0; j < n; ++j) v(1, j) = 0.01 * std::sin((n - j) * theta);
  c.set_state(c.positions(), v);
  const double y_rest = c.model().x0(1, 0);
  // time the upward zero crossings of the bottom particle's displacement
  const double h = 1e-4, period = 2 * M_PI / omega;
  double previous = 0.0, first = -1.0, last = -1.0;
  int crossings = 0;
  for (int i = 0; i < static_cast<int>(6 * period / h); ++i) {
    c.step(h);
    const double d = c.positions()(1, 0) - y_rest;
    if (previous < 0 && d >= 0) {
      const double t = c.time() - h * d / (d - previous);  // linear interpolation
      if (first < 0) first = t;
      last = t;
      ++crossings;
    }
    previous = d;
  }
  REQUIRE(crossings >= 5);
  const double measured = 2 * M_PI * (crossings - 1) / (last - first);
  INFO(integrator_name(integrator) << ": measured " << measured << " rad/s, analytic " << omega);
  CHECK(measured == Approx(omega).epsilon(tol::kEigenfrequencyRelative));
}
