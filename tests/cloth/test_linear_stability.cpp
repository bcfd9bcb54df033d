#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "cloth/analysis/linear_stability.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "cloth/model/model.hpp"
#include "test_scenes.hpp"
#include "tolerances.hpp"

using namespace cloth;

namespace {

// one free particle of mass m on a spring k (damper c) to a pinned one
Model two_particles(double m, double k, double c) {
  return build_model(clothbench::test::one_spring(m, k, c));
}

}  // namespace

TEST_CASE("the spectrum of one spring is k / m with damping c / k", "[integrator][stability]") {
  const LinearSpectrum s = linear_spectrum(two_particles(0.5, 200.0, 3.0));
  CHECK(s.omega_max == Approx(std::sqrt(200.0 / 0.5)).epsilon(1e-10));
  CHECK(s.beta == Approx(3.0 / 200.0).epsilon(1e-12));
  CHECK(s.exact);
}

TEST_CASE("predicted limits of a two-particle spring equal the closed forms",
          "[integrator][stability]") {
  const double m = 0.5, k = 200.0;
  const double w2 = k / m, w = std::sqrt(w2);
  SECTION("undamped") {
    const LinearSpectrum s = linear_spectrum(two_particles(m, k, 0.0));
    // rk4 reaches 2 sqrt(2) on the imaginary axis, symplectic Euler h w = 2, picard h w = 1
    CHECK(predicted_stable_dt(Integrator::rk4, s) == Approx(2 * std::sqrt(2.0) / w).epsilon(1e-6));
    CHECK(predicted_stable_dt(Integrator::symplectic_euler, s) == Approx(2.0 / w).epsilon(1e-6));
    CHECK(predicted_stable_dt(Integrator::picard_implicit, s) == Approx(1.0 / w).epsilon(1e-6));
    // explicit Euler and midpoint grow every undamped oscillation, at any step; growth
    // below 1e-12 per step (|R| - 1 ~ (h w)^2 / 2 and (h w)^4 / 8) counts as round-off,
    // which puts the limits at h w ~ 1.4e-6 and 5.3e-3 instead of 0
    CHECK(predicted_stable_dt(Integrator::explicit_euler, s) * w < 2e-6);
    CHECK(predicted_stable_dt(Integrator::midpoint, s) * w < 6e-3);
    CHECK(std::isinf(predicted_stable_dt(Integrator::implicit_euler, s)));
    // imex-euler without damping is symplectic Euler: h w = 2
    CHECK(predicted_stable_dt(Integrator::imex_euler, s) == Approx(2.0 / w).epsilon(1e-6));
  }
  SECTION("underdamped") {
    const double c = 1.0, a = c / m;  // a^2 = 4 < 4 w^2 = 1600
    const LinearSpectrum s = linear_spectrum(two_particles(m, k, c));
    // |1 + h lambda|^2 <= 1  <=>  h <= -2 Re(lambda) / |lambda|^2 = a / w^2 = c / k
    CHECK(predicted_stable_dt(Integrator::explicit_euler, s) == Approx(c / k).epsilon(1e-6));
    // symplectic Euler: det = 1 - h a, trace condition h^2 w^2 + 2 a h <= 4
    CHECK(predicted_stable_dt(Integrator::symplectic_euler, s) ==
          Approx((std::sqrt(a * a + 4 * w2) - a) / w2).epsilon(1e-6));
    // imex-euler: det = 1 / (1 + h a), trace condition h^2 w^2 <= 4 + 2 a h
    CHECK(predicted_stable_dt(Integrator::imex_euler, s) ==
          Approx((std::sqrt(a * a + 4 * w2) + a) / w2).epsilon(1e-6));
  }
  SECTION("overdamped") {
    const double c = 100.0, a = c / m;  // a^2 = 40000 > 4 w^2
    const LinearSpectrum s = linear_spectrum(two_particles(m, k, c));
    const double fast = 0.5 * (a + std::sqrt(a * a - 4 * w2));  // |lambda| of the fast root
    // real negative z: explicit Euler and midpoint need z >= -2, picard z >= -1
    CHECK(predicted_stable_dt(Integrator::explicit_euler, s) == Approx(2.0 / fast).epsilon(1e-6));
    CHECK(predicted_stable_dt(Integrator::midpoint, s) == Approx(2.0 / fast).epsilon(1e-6));
    CHECK(predicted_stable_dt(Integrator::picard_implicit, s) == Approx(1.0 / fast).epsilon(1e-6));
    // rk4's real-axis limit is the root of 1 + z + z^2/2 + z^3/6 + z^4/24 = 1, z ~ -2.785
    CHECK(predicted_stable_dt(Integrator::rk4, s) * fast == Approx(2.785293563).epsilon(1e-6));
    CHECK(predicted_stable_dt(Integrator::symplectic_euler, s) ==
          Approx((std::sqrt(a * a + 4 * w2) - a) / w2).epsilon(1e-6));
    CHECK(limiting_mode(Integrator::explicit_euler, s).find("overdamped") != std::string::npos);
    // imex-euler's implicit damping: h^2 w^2 <= 4 + 2 a h, a hundred times symplectic Euler
    CHECK(predicted_stable_dt(Integrator::imex_euler, s) ==
          Approx((std::sqrt(a * a + 4 * w2) + a) / w2).epsilon(1e-6));
  }
}

TEST_CASE("Lanczos finds the top frequency of a chain", "[stability]") {
  // n free masses below a pin: omega_max = 2 sqrt(k / m) sin(n pi / (2 (2 n + 1)))
  Scene s;
  const int n = 40;
  s.cloth.nu = 1;
  s.cloth.nv = n + 1;
  s.cloth.size_u = 0.0;
  s.cloth.size_v = 4.0;
  s.cloth.plane = Plane::xy;
  s.cloth.particle_mass = 0.1;
  s.cloth.k_structural = 100.0;
  s.cloth.k_shear = s.cloth.k_bend = 0.0;
  s.held.assign(n + 1, 0);
  s.held[n] = kHoldAll;
  const LinearSpectrum sp = linear_spectrum(build_model(s));
  const double theta = (2 * n - 1) * M_PI / (2 * n + 1);
  CHECK(sp.omega_max == Approx(2 * std::sqrt(1000.0) * std::sin(theta / 2)).epsilon(1e-8));
}

namespace {

// an 8 x 8 cloth on its four corners, flat and at rest, no gravity: the rest state is an
// equilibrium, so a small perturbation of it follows the linearisation exactly
Scene resting_cloth(double k_bend, double damping) {
  Scene s;
  s.cloth.nu = s.cloth.nv = 8;
  s.cloth.size_u = s.cloth.size_v = 0.7;
  s.cloth.particle_mass = 0.01;
  s.cloth.k_structural = s.cloth.k_shear = 100.0;
  s.cloth.k_bend = k_bend;
  s.cloth.damping = damping;
  s.gravity.setZero();
  s.held.assign(64, 0);
  for (int p : {0, 7, 56, 63}) s.held[static_cast<size_t>(p)] = kHoldAll;
  return s;
}

// largest displacement from rest, relative to the first one, over up to 10 s of steps of h
// (stopping once it has grown 1e6-fold)
double perturbation_growth(const Scene& scene, Integrator integrator, double h) {
  SolverOptions o;
  o.integrator = integrator;
  MassSpringCloth c(scene, o);
  const Model m = build_model(scene);
  Matrix3X x = m.x0;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += 1e-9 * std::sin(1.3 * double(i));
  c.set_state(x, Matrix3X::Zero(3, m.particle_count()));
  const double d0 = (c.positions() - m.x0).cwiseAbs().maxCoeff();
  double growth = 0.0;
  for (int k = 0; k < static_cast<int>(10.0 / h) && growth < 1e6; ++k) {
    c.step(h);
    growth = std::max(growth, (c.positions() - m.x0).cwiseAbs().maxCoeff() / d0);
  }
  return growth;
}

}  // namespace

TEST_CASE("perturbations of the rest state decay below the predicted limit and grow above it",
          "[integrator][stability][slow]") {
  const Integrator integrator =
      GENERATE(Integrator::explicit_euler, Integrator::symplectic_euler,
               Integrator::picard_implicit, Integrator::midpoint, Integrator::rk4);
  // damping proportional to stiffness, then bend springs ten times softer than the others on
  // the same heavy dampers: modes of K that D couples, several of them overdamped
  const bool proportional = GENERATE(true, false);
  const Scene scene = proportional ? resting_cloth(100.0, 0.3) : resting_cloth(10.0, 1.0);
  const LinearSpectrum s = linear_spectrum(build_model(scene));
  CHECK(s.exact == proportional);
  const double h = predicted_stable_dt(integrator, s);
  INFO(integrator_name(integrator) << (proportional ? ", proportional" : ", coupled")
                                   << " damping: predicted " << h << " s; " << s.method);
  CHECK(perturbation_growth(scene, integrator, (1 - clothbench::tol::kLinearLimitMargin) * h) <
        10.0);
  CHECK(perturbation_growth(scene, integrator, (1 + clothbench::tol::kLinearLimitMargin) * h) >
        1e4);
}

TEST_CASE("without the dense analysis non-proportional damping is only approximated",
          "[stability]") {
  // the same coupled scene with the dense analysis turned off: the top mode's damping for
  // every mode, which here overestimates every explicit limit (the reason for the dense one)
  const Scene scene = resting_cloth(10.0, 1.0);
  const LinearSpectrum dense = linear_spectrum(build_model(scene));
  const LinearSpectrum rough = linear_spectrum(build_model(scene), 200, 0);
  CHECK_FALSE(rough.exact);
  CHECK(rough.modes.empty());
  CHECK(rough.method.find("approximated") != std::string::npos);
  CHECK(dense.modes.size() == 180);  // every free DOF
  CHECK(predicted_stable_dt(Integrator::explicit_euler, rough) >
        1.1 * predicted_stable_dt(Integrator::explicit_euler, dense));
}
