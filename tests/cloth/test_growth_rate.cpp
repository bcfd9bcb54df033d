#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <vector>

#include "cloth/analysis/growth_rate.hpp"
#include "cloth/analysis/linear_stability.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "cloth/model/model.hpp"
#include "test_scenes.hpp"
#include "tolerances.hpp"

using namespace cloth;
namespace tol = clothbench::tol;
using cplx = std::complex<double>;

namespace {

/// One particle of mass m on a spring k (damper c) along x to a pinned particle, free along x
/// only: its state (x, v) obeys x'' = -w2 x - g x' with w2 = k / m and g = c / m exactly (the
/// spring stays along x, so its force is linear in x).
Scene one_spring(double m, double k, double c) {
  Scene s = clothbench::test::one_spring(m, k, c);
  s.held[1] = kHoldY | kHoldZ;
  return s;
}

/// One step of integrator i on x'' = -w2 x - g x', written from the methods' definitions:
/// A = [0 1; -w2 -g] and each method's update of (x, v).
Eigen::Matrix2d step_matrix(Integrator i, double h, double w2, double g) {
  Eigen::Matrix2d a;
  a << 0.0, 1.0, -w2, -g;
  const Eigen::Matrix2d ha = h * a, id = Eigen::Matrix2d::Identity();
  switch (i) {
    case Integrator::explicit_euler:
      return id + ha;
    case Integrator::symplectic_euler: {
      // v1 = v + h (-w2 x - g v), then x1 = x + h v1
      Eigen::Matrix2d s;
      s << 1.0 - h * h * w2, h * (1.0 - h * g), -h * w2, 1.0 - h * g;
      return s;
    }
    case Integrator::midpoint:
      return id + ha + ha * ha / 2.0;
    case Integrator::picard_implicit:
      // s1 = s + h A (s + h A s)
      return id + ha + ha * ha;
    case Integrator::rk4:
      return id + ha + ha * ha / 2.0 + ha * ha * ha / 6.0 + ha * ha * ha * ha / 24.0;
    default:
      throw std::logic_error("no closed form");
  }
}

/// The eigenvalue of largest modulus of a 2 by 2 matrix from its trace and determinant; of a
/// complex pair the one with positive imaginary part.
cplx dominant_eigenvalue(const Eigen::Matrix2d& s) {
  const double half = 0.5 * s.trace();
  const cplx root = std::sqrt(cplx(half * half - s.determinant(), 0.0));
  const cplx a = half + root, b = half - root;
  if (std::abs(std::abs(a) - std::abs(b)) <= 1e-14 * std::abs(a)) return a.imag() >= 0 ? a : b;
  return std::abs(a) > std::abs(b) ? a : b;
}

/// The step (s) at which the closed-form spectral radius crosses 1, by bisection between a
/// stable lo and an unstable hi.
double closed_form_limit(Integrator i, double w2, double g, double lo, double hi) {
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (std::abs(dominant_eigenvalue(step_matrix(i, mid, w2, g))) > 1.0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

/// The growth of the engine's own state after `before` steps of dt.
GrowthEstimate measure(const Scene& s, const SolverOptions& so, double dt, int steps,
                       const GrowthOptions& o, int before = 0) {
  MassSpringCloth c(s, so);
  for (int i = 0; i < before; ++i) c.step(dt);
  const MapState st{c.positions(), c.velocities(), c.time()};
  return estimate_growth(c, st, dt, steps, c.model().free, o);
}

SolverOptions options(Integrator i) {
  SolverOptions o;
  o.integrator = i;
  return o;
}

}  // namespace

TEST_CASE("growth of one spring equals the spectral radius of the closed-form step matrix",
          "[growth]") {
  const Integrator i = GENERATE(Integrator::explicit_euler, Integrator::symplectic_euler,
                                Integrator::midpoint, Integrator::picard_implicit, Integrator::rk4);
  const double c = GENERATE(0.0, 0.5);
  const double h = GENERATE(0.01, 0.05);
  const int steps = GENERATE(1, 3);
  const double m = 0.1, k = 100.0;
  const Eigen::Matrix2d s1 = step_matrix(i, h, k / m, c / m);
  Eigen::Matrix2d s = Eigen::Matrix2d::Identity();
  for (int n = 0; n < steps; ++n) s = s1 * s;
  const cplx expected = dominant_eigenvalue(s);
  const GrowthEstimate g = measure(one_spring(m, k, c), options(i), h, steps, {});
  INFO(integrator_name(i) << " c " << c << " h " << h << " steps " << steps << ": rho " << g.rho
                          << " closed form " << std::abs(expected) << ", eigenvalue "
                          << g.eigenvalue << " closed form " << expected << ", products "
                          << g.products);
  CHECK(g.converged);
  CHECK(g.residual <= GrowthOptions{}.rel_tol * g.rho);
  CHECK(g.smooth);
  CHECK(g.rho == Approx(std::abs(expected)).epsilon(tol::kGrowthLinearRelative));
  CHECK(std::abs(g.eigenvalue - expected) <= tol::kGrowthLinearRelative * std::abs(expected));
  CHECK(g.rate == Approx(std::log(std::abs(expected)) / (steps * h))
                      .margin(tol::kGrowthLinearRelative / (steps * h)));
  // the mode: the position entry is 1 and the held axes 0
  CHECK(g.mode(0, 1) == Approx(1.0).margin(tol::kGrowthLinearRelative));
  CHECK(g.mode.col(0).isZero());
  CHECK(g.mode(1, 1) == 0.0);
}

TEST_CASE("one step just past the closed-form limit grows, just below it does not", "[growth]") {
  const Integrator i =
      GENERATE(Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::rk4);
  const double m = 0.1, k = 100.0, c = 0.5, w2 = k / m, g = c / m;
  // stable at 1e-4 s for all three; unstable at 0.2 s (h w = 6.3)
  const double limit = closed_form_limit(i, w2, g, 1e-4, 0.2);
  const double factor = GENERATE(0.99, 1.01);
  const double h = factor * limit;
  const double expected = std::abs(dominant_eigenvalue(step_matrix(i, h, w2, g)));
  const GrowthEstimate e = measure(one_spring(m, k, c), options(i), h, 1, {});
  INFO(integrator_name(i) << " limit " << limit << " s, h " << h << ": rho " << e.rho
                          << " closed form " << expected);
  CHECK(e.rho == Approx(expected).epsilon(tol::kGrowthLinearRelative));
  if (factor > 1)
    CHECK(e.rho > 1.0);
  else
    CHECK(e.rho < 1.0);
}

TEST_CASE("an inverted pendulum's growth rate is the flow's: sqrt(g / l) at dt and at dt / 8",
          "[growth]") {
  const Integrator i = GENERATE(Integrator::rk4, Integrator::symplectic_euler);
  // one particle on a stiff spring standing on a pinned one, at its equilibrium: the spring
  // shortened by m g / k to length l, so a sideways tilt u grows as u'' = (g / l) u (the
  // spring's compression m g pushes out by m g u / l) on both horizontal axes
  const double m = 0.1, k = 1000.0, rest = 0.2, g = 9.8;
  Scene s;
  s.cloth.nu = 1;
  s.cloth.nv = 2;
  s.cloth.size_u = 0.0;
  s.cloth.size_v = rest;
  s.cloth.plane = Plane::xy;
  s.cloth.particle_mass = m;
  s.cloth.k_structural = k;
  s.cloth.k_shear = s.cloth.k_bend = 0.0;
  s.cloth.damping = 0.5;
  s.gravity = {0.0, -g, 0.0};
  s.held = {kHoldAll, 0};
  MassSpringCloth c(s, options(i));
  const double l = rest - m * g / k;
  Matrix3X x = c.positions();
  x.col(1) = x.col(0) + Vector3(0.0, l, 0.0);
  const MapState st{x, Matrix3X::Zero(3, 2), 0.0};
  GrowthOptions o;
  o.rel_tol = 1e-6;
  // the map over 0.1 s: 100 steps of 1 ms, then 800 of 0.125 ms
  const GrowthEstimate coarse = estimate_growth(c, st, 1e-3, 100, c.model().free, o);
  const GrowthEstimate fine = estimate_growth(c, st, 1.25e-4, 800, c.model().free, o);
  const double sigma = std::sqrt(g / l);
  INFO(integrator_name(i) << ": rate " << coarse.rate << " and " << fine.rate << " 1/s against "
                          << sigma << ", rho " << coarse.rho << " and " << fine.rho << ", products "
                          << coarse.products << " and " << fine.products);
  CHECK(coarse.converged);
  CHECK(fine.converged);
  CHECK(coarse.smooth);
  CHECK(fine.smooth);
  CHECK(coarse.rate == Approx(fine.rate).margin(tol::kGrowthRateAcrossSteps));
  CHECK(fine.rate == Approx(sigma).margin(tol::kGrowthRateAcrossSteps));
  // the mode tilts the pendulum: no vertical part
  CHECK(std::abs(coarse.mode(1, 1)) < 1e-3);
}

TEST_CASE("growth refuses a perturbation at round-off and an empty Krylov space", "[growth]") {
  MassSpringCloth c(one_spring(0.1, 100.0, 0.5), options(Integrator::rk4));
  const MapState st{c.positions(), c.velocities(), 0.0};
  GrowthOptions o;
  o.perturbation = 1e-13;
  CHECK_THROWS_AS(estimate_growth(c, st, 1e-3, 1, c.model().free, o), std::invalid_argument);
  o = GrowthOptions{};
  o.max_iterations = 0;
  CHECK_THROWS_AS(estimate_growth(c, st, 1e-3, 1, c.model().free, o), std::invalid_argument);
  o = GrowthOptions{};
  CHECK_THROWS_AS(estimate_growth(c, st, 0.0, 1, c.model().free, o), std::invalid_argument);
  CHECK_THROWS_AS(estimate_growth(c, st, 1e-3, 0, c.model().free, o), std::invalid_argument);
  CHECK_NOTHROW(estimate_growth(c, st, 1e-3, 1, c.model().free, o));
}

TEST_CASE("a particle exactly on a collider's contact shell makes the map non-smooth", "[growth]") {
  // one particle on a spring along x, free on every axis, no gravity: at rest it stays put
  Scene s = one_spring(0.1, 100.0, 0.5);
  s.held = {kHoldAll, 0};
  const Vector3 at = build_model(s).x0.col(1);
  const bool sphere = GENERATE(false, true);
  const bool touching = GENERATE(true, false);
  // below the particle, its shell through it (touching) or 10 cm lower
  const double gap = touching ? 0.0 : 0.1;
  if (sphere) {
    Sphere b;
    b.radius = 0.2;
    b.center = at - Vector3(0.0, b.radius + b.margin + gap, 0.0);
    s.spheres.push_back(b);
  } else {
    HalfSpace f;
    f.point = at - Vector3(0.0, f.margin + gap, 0.0);
    s.shapes.planes.push_back(f);
  }
  const GrowthEstimate e = measure(s, options(Integrator::symplectic_euler), 1e-3, 1, {});
  INFO((sphere ? "sphere" : "plane")
       << (touching ? " touching" : " apart") << ": " << e.nonsmooth_reason);
  CHECK(e.smooth == !touching);
  CHECK(e.nonsmooth_reason.empty() == !touching);
}

TEST_CASE("growth at the rest state of a grid equals the linear predictor's radius", "[growth]") {
  // explicit Euler's top moduli crowd together near its limit (1.0552, 1.0535, 1.0535, 1.0508
  // on this grid at 1.1 x), and below every limit the free bending modes (x' = v, v' = 0) make
  // a non-normal cluster at 1: both defeated a block iteration, not Arnoldi
  const Integrator i =
      GENERATE(Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::rk4);
  const double factor = GENERATE(0.9, 1.02, 1.1);
  Scene s = clothbench::test::small_cloth(5, 20.0, 0.5);
  s.gravity.setZero();  // the rest state is then an equilibrium
  const LinearSpectrum spectrum = linear_spectrum(build_model(s));
  REQUIRE(spectrum.exact);  // one stiffness for every kind: the modes decouple
  const double h = factor * predicted_stable_dt(i, spectrum);
  // the predictor's radius: the top mode's (every omega of [0, omega_max] was checked by the
  // limit; the radius of these methods grows with omega past it)
  double predicted = 1.0;  // the modes of zero frequency (a flat cloth bends freely)
  for (int n = 0; n <= 1000; ++n) {
    const double w = spectrum.omega_max * n / 1000.0;
    predicted = std::max(predicted, mode_radius(i, h, w, spectrum.beta, spectrum.gamma));
  }
  if (factor > 1)
    CHECK(predicted ==
          Approx(mode_radius(i, h, spectrum.omega_max, spectrum.beta, spectrum.gamma)));
  GrowthOptions o;
  o.rel_tol = 1e-6;
  o.max_iterations = 400;
  const GrowthEstimate e = measure(s, options(i), h, 1, o);
  INFO(integrator_name(i) << " at " << factor << " x the limit: rho " << e.rho << " predicted "
                          << predicted << ", " << e.iterations << " iterations, " << e.products
                          << " products");
  CHECK(e.converged);
  CHECK(e.smooth);
  if (factor > 1) {
    CHECK(e.rho > 1.0);
    CHECK(e.rho == Approx(predicted).epsilon(tol::kGrowthVsPredictor));
  } else {
    // below the limit J's largest modulus is 1 (the free bending modes), a defective
    // eigenvalue: its Ritz value is off by about the square root of the residual
    CHECK(e.rho >= 1 - tol::kGrowthDefective);
    CHECK(e.rho <= 1 + tol::kGrowthDefective);
  }
}

TEST_CASE("an estimate stopped once its side of a threshold is decided takes the true side",
          "[growth][slow]") {
  // the rest grid of the test above: near and far thresholds on both sides of J's largest
  // modulus, from the linear predictor; below every limit that is the free bending modes'
  // defective 1, whose Ritz values settle above it (the non-normal case a bound from the
  // residual alone, not its square root, is fooled by)
  const Integrator i =
      GENERATE(Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::rk4);
  const double factor = GENERATE(0.9, 1.02, 1.1);
  const double offset = GENERATE(-0.03, -1e-3, -1e-5, 1e-5, 1e-3, 0.03);
  Scene s = clothbench::test::small_cloth(5, 20.0, 0.5);
  s.gravity.setZero();
  const LinearSpectrum spectrum = linear_spectrum(build_model(s));
  const double h = factor * predicted_stable_dt(i, spectrum);
  double predicted = 1.0;
  for (int n = 0; n <= 1000; ++n) {
    const double w = spectrum.omega_max * n / 1000.0;
    predicted = std::max(predicted, mode_radius(i, h, w, spectrum.beta, spectrum.gamma));
  }
  const double threshold = predicted * (1 + offset);
  GrowthOptions o;
  o.rel_tol = 1e-6;
  o.max_iterations = 400;
  const GrowthEstimate full = measure(s, options(i), h, 1, o);
  o.decide_below = o.decide_above = threshold;
  const GrowthEstimate early = measure(s, options(i), h, 1, o);
  const int truth = predicted > threshold ? 1 : -1;
  INFO(integrator_name(i) << " at " << factor << " x the limit, threshold " << threshold
                          << ": predicted " << predicted << ", full rho " << full.rho << " in "
                          << full.products << " products, early rho " << early.rho << " decided "
                          << early.decided << " in " << early.products);
  // the full estimate is on the true side where the threshold is clear of its error (the
  // defective cluster's, tol::kGrowthDefective, below the limit)
  if (std::abs(offset) > (factor < 1 ? tol::kGrowthDefective : tol::kGrowthVsPredictor))
    CHECK((full.rho > threshold ? 1 : -1) == truth);
  // a decision is never the wrong side; undecided, the estimate is the full one; a far
  // threshold is decided unless the residual met rel_tol first
  CHECK((early.decided == 0 || early.decided == truth));
  CHECK(early.products <= full.products);
  if (early.decided == 0) CHECK(early.rho == full.rho);
  if (std::abs(offset) >= 0.03) CHECK((early.decided == truth || early.converged));
}

TEST_CASE("the side of a threshold allows the square root of the residual", "[growth]") {
  // a Jordan block [1 1; 0 1] perturbed by r in its corner has eigenvalues 1 +- sqrt(r):
  // a Ritz value of residual r may be sqrt(r) away from the eigenvalue
  const double r = 1e-6;
  Eigen::Matrix2d j;
  j << 1.0, 1.0, r, 1.0;
  const double top = std::abs(dominant_eigenvalue(j));
  CHECK(top == Approx(1 + std::sqrt(r)).epsilon(1e-12));
  // so a Ritz value 1 with residual r is undecided against a threshold within sqrt(r) of 1
  CHECK(decided_side(cplx(1.0, 0.0), r, 1 + 0.5 * std::sqrt(r), INFINITY) == 0);
  CHECK(decided_side(cplx(1.0, 0.0), r, 0.0, 1 - 0.5 * std::sqrt(r)) == 0);
  CHECK(decided_side(cplx(1.0, 0.0), r, 1 + 2 * std::sqrt(r), INFINITY) == -1);
  CHECK(decided_side(cplx(1.0, 0.0), r, 0.0, 1 - 2 * std::sqrt(r)) == 1);
  CHECK(decided_side(cplx(0.0, 1.0), r, 0.0, 1 - 2 * std::sqrt(r)) == 1);
}
