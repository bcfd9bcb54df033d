#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "cloth/forces/energies.hpp"
#include "cloth/forces/spring_forces.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "test_scenes.hpp"
#include "tolerances.hpp"

using namespace cloth;
namespace tol = clothbench::tol;

namespace {

MassSpringCloth make(const Scene& s, Integrator integrator) {
  SolverOptions o;
  o.integrator = integrator;
  o.cg_tolerance = 1e-12;  // the convergence test measures the integrator, not the solver
  return MassSpringCloth(s, o);
}

Matrix3X run(const Scene& s, Integrator integrator, double h, double duration) {
  MassSpringCloth c = make(s, integrator);
  const int steps = static_cast<int>(std::lround(duration / h));
  for (int i = 0; i < steps; ++i) c.step(h);
  return c.positions();
}

double rms_distance(const Matrix3X& a, const Matrix3X& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

// least-squares slope of log(error) against log(h)
double fitted_order(const std::vector<double>& hs, const std::vector<double>& errors) {
  const size_t n = hs.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < n; ++i) {
    const double lx = std::log(hs[i]), ly = std::log(errors[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

TEST_CASE("free fall follows y0 - g t^2 / 2 with each method's known offset", "[integrator]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  // a cloth without held particles falls rigidly: internal forces stay zero
  Scene s = clothbench::test::small_cloth(4, 500.0, 2.0);
  s.held.clear();
  const double g = 9.8, h = 1e-3;
  const int steps = 1000;
  MassSpringCloth c = make(s, integrator);
  const double y0 = c.positions().row(1).mean();
  for (int i = 0; i < steps; ++i) c.step(h);
  const double t = steps * h;
  const double exact = y0 - 0.5 * g * t * t;
  const double com_y = c.positions().row(1).mean();
  // x_{n+1} = x_n + h v_n lags by g h t / 2; updating v first leads by the same amount
  double expected = exact;
  switch (integrator) {
    case Integrator::explicit_euler:
      expected = exact + 0.5 * g * h * t;
      break;
    case Integrator::symplectic_euler:
    case Integrator::picard_implicit:
    case Integrator::implicit_euler:
    case Integrator::imex_euler:
    case Integrator::xpbd:
    case Integrator::projective:
      expected = exact - 0.5 * g * h * t;
      break;
    case Integrator::midpoint:
    case Integrator::rk4:
      break;
  }
  INFO(integrator_name(integrator));
  CHECK(com_y == Approx(expected).margin(tol::kFreeFallOffset));
  if (integrator == Integrator::midpoint || integrator == Integrator::rk4)
    CHECK(com_y == Approx(exact).margin(tol::kFreeFallExact));
  else
    CHECK(std::abs(com_y - exact) > 1e-3);  // the offset is real: 0.0049 m here
}

TEST_CASE("measured convergence order of every integrator", "[integrator]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  // smooth motion without contact: a soft cloth swinging from two corners
  const Scene s = clothbench::test::small_cloth(5, 20.0, 0.5);
  const double duration = 0.5;
  const std::vector<double> hs = {4e-3, 2e-3, 1e-3, 5e-4};
  const Matrix3X reference = run(s, Integrator::rk4, 5e-4 / 8, duration);
  std::vector<double> errors;
  for (double h : hs) errors.push_back(rms_distance(run(s, integrator, h, duration), reference));
  const double order = fitted_order(hs, errors);
  INFO(integrator_name(integrator) << " errors " << errors[0] << " " << errors[1] << " "
                                   << errors[2] << " " << errors[3] << " order " << order);
  CHECK(order == Approx(integrator_order(integrator)).margin(tol::kOrderMargin));
}

TEST_CASE("undamped energy: symplectic bounded, explicit grows, implicit decays, rk4 best",
          "[integrator]") {
  const Scene s = clothbench::test::small_cloth(5, 20.0, 0.0);
  const double h = 2e-3, duration = 4.0;
  const int steps = static_cast<int>(std::lround(duration / h));
  struct Drift {
    double final = 0;        // E(T) - E(0)
    double max_first = 0;    // max |E - E0| over the first half
    double max_second = 0;   // max |E - E0| over the second half
    double max_kinetic = 0;  // scale of the energy the swing exchanges
  };
  auto drift = [&](Integrator integrator) {
    MassSpringCloth c = make(s, integrator);
    const Model& m = c.model();
    const double e0 = compute_energies(m, c.positions(), c.velocities()).total();
    Drift d;
    for (int i = 0; i < steps; ++i) {
      c.step(h);
      const Energies e = compute_energies(m, c.positions(), c.velocities());
      const double de = std::abs(e.total() - e0);
      (i < steps / 2 ? d.max_first : d.max_second) =
          std::max(i < steps / 2 ? d.max_first : d.max_second, de);
      d.max_kinetic = std::max(d.max_kinetic, e.kinetic);
      d.final = e.total() - e0;
    }
    return d;
  };
  const Drift ex = drift(Integrator::explicit_euler), sy = drift(Integrator::symplectic_euler),
              im = drift(Integrator::implicit_euler), rk = drift(Integrator::rk4),
              mid = drift(Integrator::midpoint);
  INFO("final drift: explicit " << ex.final << " symplectic " << sy.final << " implicit "
                                << im.final << " rk4 " << rk.final << " midpoint " << mid.final
                                << "; symplectic max |dE| " << sy.max_first << " then "
                                << sy.max_second << ", max kinetic " << sy.max_kinetic);
  // explicit Euler gains and implicit Euler loses a sizeable part of the swing's energy
  CHECK(ex.final > 0.1 * ex.max_kinetic);
  CHECK(im.final < -0.1 * sy.max_kinetic);
  // symplectic Euler's error oscillates without growing: the second half is no worse
  CHECK(sy.max_second < 1.5 * sy.max_first);
  CHECK(sy.max_second < 0.05 * sy.max_kinetic);
  CHECK(ex.max_second > 2.0 * ex.max_first);
  // rk4 drifts least of all
  for (const Drift* other : {&ex, &sy, &im, &mid})
    CHECK(std::abs(rk.final) < std::abs(other->final));
}

TEST_CASE("total energy plus dissipated energy is conserved as h shrinks", "[integrator]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  const Scene s = clothbench::test::small_cloth(5, 20.0, 0.5);
  struct Result {
    double error, dissipated;
  };
  auto run_energy = [&](double h) {
    MassSpringCloth c = make(s, integrator);
    const double e0 = compute_energies(c.model(), c.positions(), c.velocities()).total();
    for (int i = 0; i < static_cast<int>(std::lround(1.0 / h)); ++i) c.step(h);
    const double e1 = compute_energies(c.model(), c.positions(), c.velocities()).total();
    return Result{e1 + c.dissipated() - e0, c.dissipated()};
  };
  const Result coarse = run_energy(2e-3), fine = run_energy(1e-3);
  INFO(integrator_name(integrator)
       << " error " << coarse.error << " -> " << fine.error << ", dissipated " << fine.dissipated);
  CHECK(fine.dissipated > 0.01);  // the dampers really work in this scene
  // the balance error is the method's truncation error: it falls at least linearly with h
  CHECK(std::abs(fine.error) < 0.6 * std::abs(coarse.error));
  if (integrator == Integrator::rk4) CHECK(std::abs(fine.error) < 1e-6 * fine.dissipated);
}

TEST_CASE("held axes stay bit-identical in every integrator", "[integrator]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  // one pinned corner (xyz), a curtain edge (y and z held) and a table particle (y held)
  Scene s = clothbench::test::small_cloth(5, 200.0, 1.0);
  s.gravity = {0.7, -9.8, 0.3};
  s.held.assign(25, 0);
  s.held[0] = kHoldAll;
  for (int i = 1; i < 5; ++i) s.held[static_cast<size_t>(i)] = kHoldY | kHoldZ;
  s.held[12] = kHoldY;
  MassSpringCloth c = make(s, integrator);
  const Matrix3X x0 = c.positions();
  for (int i = 0; i < 300; ++i) c.step(2e-3);
  const Matrix3X& x = c.positions();
  INFO(integrator_name(integrator));
  CHECK(x.col(0) == x0.col(0));
  for (int i = 1; i < 5; ++i) {
    CHECK(x(1, i) == x0(1, i));
    CHECK(x(2, i) == x0(2, i));
    CHECK(x(0, i) != x0(0, i));  // the curtain edge does slide along x
  }
  CHECK(x(1, 12) == x0(1, 12));
  CHECK(x(0, 12) != x0(0, 12));
  CHECK(x(1, 13) != x0(1, 13));  // and a free particle does move
}

TEST_CASE("implicit Euler is stable on the seed scene at h = 1/30 s", "[integrator]") {
  SolverOptions o;
  o.integrator = Integrator::implicit_euler;
  MassSpringCloth c(seed_scene(), o);
  const double h = 1.0 / 30.0;
  double worst_strain = 0.0;
  for (int i = 0; i < 90; ++i) {  // 3 s
    c.step(h);
    const StrainStats st = strain_stats(c.model().springs, c.positions());
    REQUIRE(std::isfinite(st.max_abs));
    worst_strain = std::max(worst_strain, st.max_abs);
  }
  INFO("largest strain " << worst_strain << ", CG iterations " << c.counters().cg_iterations);
  CHECK(worst_strain < 0.5);
  // the cloth has come to rest draped over the sphere
  CHECK(c.velocities().cwiseAbs().maxCoeff() < 0.05);
  CHECK(c.positions().row(1).maxCoeff() < 1.02);
}

TEST_CASE("explicit methods count their force evaluations", "[integrator]") {
  const Integrator integrator = GENERATE(from_range(all_integrators()));
  MassSpringCloth c = make(clothbench::test::small_cloth(), integrator);
  for (int i = 0; i < 10; ++i) c.step(1e-3);
  CHECK(c.counters().steps == 10);
  // xpbd sweeps the springs iterations times per substep, projective iterations times
  const bool iterates = integrator == Integrator::xpbd || integrator == Integrator::projective;
  const int per_step = force_evals_per_step(integrator) *
                       (iterates ? c.options().iterations * c.options().substeps : 1);
  CHECK(c.counters().force_evals == 10 * per_step);
  if (integrator == Integrator::implicit_euler || integrator == Integrator::imex_euler)
    CHECK(c.counters().cg_iterations >= 10);
}
