// XPBD and projective dynamics (fast mass-springs): the physical facts that hold for them.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "cloth/forces/energies.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "test_scenes.hpp"

using namespace cloth;

namespace {

SolverOptions method(Integrator i, int iterations, int substeps = 1) {
  SolverOptions o;
  o.integrator = i;
  o.iterations = iterations;
  o.substeps = substeps;
  return o;
}

/// Largest relative error of the settled chain's stretches against discrete statics: the
/// spring above particle j carries the j + 1 particles below it, stretch (j + 1) m g / k.
double chain_statics_error(const SolverOptions& o, double h, double seconds) {
  const int n = 10;
  const double m = 0.1, k = 100.0, l = 0.1, g = 9.8;
  MassSpringCloth c(clothbench::test::chain(n, m, k, l, 5.0, g), o);
  for (int i = 0; i < static_cast<int>(seconds / h); ++i) c.step(h);
  double worst = 0;
  for (int j = 0; j < n; ++j) {
    const double stretch = (c.positions().col(j + 1) - c.positions().col(j)).norm() - l;
    const double expected = (j + 1) * m * g / k;
    worst = std::max(worst, std::abs(stretch / expected - 1));
  }
  return worst;
}

}  // namespace

TEST_CASE("xpbd: a hanging chain's statics converge to the springs' as iterations grow",
          "[integrator][xpbd]") {
  // with few sweeps per substep the constraints are not solved and the chain hangs too long
  // (by about g h_s^2 per sweep short of convergence); the error falls as sweeps are added
  const double h = 1.0 / 60;
  std::vector<double> errors;
  for (int iterations : {2, 8, 32, 128})
    errors.push_back(chain_statics_error(method(Integrator::xpbd, iterations), h, 30.0));
  INFO("errors at 2, 8, 32, 128 iterations: " << errors[0] << " " << errors[1] << " " << errors[2]
                                              << " " << errors[3]);
  // ... down to round-off (1e-10 of a stretch) from 32 sweeps on
  for (size_t i = 1; i < errors.size(); ++i) CHECK((errors[i] < errors[i - 1] || errors[i] < 1e-8));
  CHECK(errors.back() < 1e-8);
  // small steps, one sweep per substep: the damping term's share of each projection leaves
  // the statics off by O(c h_s / m), first order in the substep (0.106, 0.026 and 0.0065 of
  // the stretch at 16, 64 and 256 substeps here): each fourfold refinement quarters it
  const double e16 = chain_statics_error(method(Integrator::xpbd, 1, 16), h, 30.0);
  const double e64 = chain_statics_error(method(Integrator::xpbd, 1, 64), h, 30.0);
  const double e256 = chain_statics_error(method(Integrator::xpbd, 1, 256), h, 30.0);
  INFO("one sweep at 16, 64, 256 substeps: " << e16 << " " << e64 << " " << e256);
  CHECK(e16 / e64 == Approx(4).epsilon(0.1));
  CHECK(e64 / e256 == Approx(4).epsilon(0.1));
}

TEST_CASE("projective: a hanging chain settles where discrete statics put it",
          "[integrator][projective]") {
  // a fixed point of the local/global iterations is a backward-Euler step, whose rest state is
  // the springs' equilibrium at any h; the iterations converge there (slowly on a stiff chain)
  const double coarse = chain_statics_error(method(Integrator::projective, 2), 1.0 / 60, 30.0);
  const double fine = chain_statics_error(method(Integrator::projective, 50), 1.0 / 60, 30.0);
  INFO("2 iterations: " << coarse << ", 50 iterations: " << fine);
  CHECK(fine < 1e-4);
}

TEST_CASE("projective converges to backward Euler's step as iterations grow",
          "[integrator][projective]") {
  // one step of 1/30 s from a moving, stretched state; backward Euler solved by Newton with
  // a line search to a tight residual is the limit the local/global iterations approach
  const Scene s = clothbench::test::small_cloth(6, 200.0, 0.5);
  SolverOptions exact = line_search_options(LinearSolver::ldlt);
  exact.newton_tolerance = 1e-12;
  exact.newton_iterations = 50;
  const double h = 1.0 / 30;
  MassSpringCloth be(s, exact);
  Matrix3X v = Matrix3X::Zero(3, be.model().particle_count());
  for (Eigen::Index p = 0; p < v.cols(); ++p) v(1, p) = -0.5 + 0.1 * std::sin(double(p));
  be.set_state(be.positions(), v);
  be.step(h);
  std::vector<double> errors;
  for (int iterations : {1, 4, 16, 64, 256, 1024}) {
    MassSpringCloth pd(s, method(Integrator::projective, iterations));
    pd.set_state(pd.positions(), v);
    pd.step(h);
    errors.push_back((pd.positions() - be.positions()).cwiseAbs().maxCoeff());
  }
  INFO("max |x_pd - x_be| (m) at 1, 4, 16, 64, 256, 1024 iterations: "
       << errors[0] << " " << errors[1] << " " << errors[2] << " " << errors[3] << " " << errors[4]
       << " " << errors[5]);
  for (size_t i = 1; i < errors.size(); ++i)
    CHECK((errors[i] < errors[i - 1] || errors[i] < 1e-11));
  // to the accuracy backward Euler was solved to
  CHECK(errors.back() < 1e-10);
}

TEST_CASE("xpbd and projective gain no energy from rest, and keep held axes exact",
          "[integrator][xpbd][projective]") {
  const SolverOptions o = GENERATE(method(Integrator::xpbd, 10), method(Integrator::xpbd, 1, 8),
                                   method(Integrator::projective, 10));
  INFO(integrator_name(o.integrator)
       << ", " << o.iterations << " iterations, " << o.substeps << " substeps");
  for (double damping : {0.0, 0.5}) {
    MassSpringCloth c(clothbench::test::small_cloth(6, 200.0, damping), o);
    const Model& m = c.model();
    const double e0 = compute_energies(m, c.positions(), c.velocities()).total();
    double worst_gain = -1e300;
    for (int i = 0; i < 120; ++i) {
      c.step(1.0 / 60);
      const double e = compute_energies(m, c.positions(), c.velocities()).total();
      // a passive cloth released from rest can only lose energy
      worst_gain = std::max(worst_gain, e - e0);
    }
    INFO("damping " << damping << ": largest energy gain " << worst_gain << " J");
    CHECK(worst_gain <= 1e-9 * std::abs(e0) + 1e-12);
    // the two held corners never moved, to the bit
    for (Eigen::Index p = 0; p < m.particle_count(); ++p)
      for (int r = 0; r < 3; ++r)
        if (m.free(r, p) == 0.0) {
          CHECK(c.positions()(r, p) == m.x0(r, p));
          CHECK(c.velocities()(r, p) == 0.0);
        }
  }
}
