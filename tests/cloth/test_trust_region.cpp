#include <catch2/catch.hpp>
#include <cmath>

#include "cloth/integrators/mass_spring_cloth.hpp"
#include "cloth/solvers/trust_region_cg.hpp"
#include "test_scenes.hpp"

using namespace cloth;

namespace {

constexpr double kStep = 1.0 / 30.0;  // s, the large step

/// Issue 30's fabric (examples/large_steps/fabric_128.toml) without its sphere: a 1 m square of
/// 0.2 kg on an n x n grid, springs 500 / 500 / 5 N/m, flat and horizontal, held along i = 0.
Scene held_fabric(int n) {
  Scene s;
  s.cloth.nu = n;
  s.cloth.nv = n;
  s.cloth.size_u = 1.0;
  s.cloth.size_v = 1.0;
  s.cloth.center = {0.0, 0.8, 0.0};
  s.cloth.plane = Plane::xz;
  s.cloth.particle_mass = 0.2 / (n * n);
  s.cloth.k_structural = 500.0;
  s.cloth.k_shear = 500.0;
  s.cloth.k_bend = 5.0;
  s.cloth.damping = 0.01;
  s.held.assign(static_cast<size_t>(n * n), 0);
  for (int j = 0; j < n; ++j) s.held[static_cast<size_t>(particle_index(s.cloth, 0, j))] = kHoldAll;
  return s;
}

/// Implicit Euler with newton = method and the line-search mode's other defaults.
SolverOptions newton_options(NewtonMethod method) {
  SolverOptions o = line_search_options(LinearSolver::block_jacobi_cg);
  o.newton = method;
  return o;
}

/// One step of scene s from (x, v) with options o.
MassSpringCloth one_step(const Scene& s, const SolverOptions& o, const Matrix3X& x,
                         const Matrix3X& v) {
  MassSpringCloth c(s, o);
  c.set_state(x, v);
  c.step(kStep);
  return c;
}

}  // namespace

TEST_CASE("trust-region CG stops on the region's edge along negative curvature", "[trust-region]") {
  // a 2 by 1 problem: A = diag(1, -1), b = (1, 1); the model falls without bound along y, so
  // the step must end on the circle of radius 2 (unit weights)
  Matrix3X b = Matrix3X::Zero(3, 1), w = Matrix3X::Ones(3, 1), s(3, 1);
  b << 1.0, 1.0, 0.0;
  auto apply = [](const Matrix3X& u, Matrix3X& out) {
    out = u;
    out(1, 0) = -u(1, 0);
  };
  auto identity = [](const Matrix3X& r, Matrix3X& z) { z = r; };
  auto none = [](Matrix3X&) {};
  CgWorkspace ws;
  ws.resize(1);
  const TrustRegionCgResult r =
      trust_region_pcg(apply, identity, none, b, w, 2.0, s, ws, 1e-12, 10);
  CHECK(r.negative_curvature);
  CHECK(r.on_boundary);
  CHECK(s.norm() == Approx(2.0).epsilon(1e-14));
  // the model's decrease as reported equals -m(s) computed directly
  const double model = -b.col(0).dot(s.col(0)) + 0.5 * (s(0, 0) * s(0, 0) - s(1, 0) * s(1, 0));
  CHECK(r.predicted_decrease == Approx(-model).epsilon(1e-14));
  CHECK(r.predicted_decrease > 0.0);
}

TEST_CASE("trust-region reaches the line search's step where the line search converges",
          "[trust-region]") {
  // a small hanging cloth swinging from two corners, from a shaken state: the line search
  // converges here; both methods solve the same equations, so they must find the same step
  const Scene s = clothbench::test::small_cloth(8, 200.0, 0.5);
  const Model m = build_model(s);
  Matrix3X v = Matrix3X::Zero(3, m.particle_count());
  for (Eigen::Index p = 0; p < v.cols(); ++p)
    v.col(p) = Vector3(std::sin(3.0 * p), std::cos(5.0 * p), 0.5 * std::sin(p + 1.0));
  v = (m.free.array() > 0.0).select(v, 0.0);
  constexpr double kResidual = 1e-9;  // m/s, |M^-1 residual| on every free axis
  auto solve = [&](NewtonMethod method) {
    SolverOptions o = newton_options(method);
    o.newton_tolerance = kResidual / kStep;
    o.newton_iterations = 200;
    o.cg_tolerance = 1e-10;
    return one_step(s, o, m.x0, v);
  };
  const MassSpringCloth ls = solve(NewtonMethod::line_search);
  const MassSpringCloth tr = solve(NewtonMethod::trust_region);
  CAPTURE(ls.counters().newton_iterations, tr.counters().newton_iterations);
  REQUIRE(ls.newton()->last_residual() <= kResidual);
  REQUIRE(tr.newton()->last_residual() <= kResidual);
  // the steps agree to within what the two residuals allow: where A >= M, |A^-1 M| <= 1 in the
  // mass norm, so they differ by at most 2 kResidual there, and by sqrt(#P) more in the max norm
  // over particles of equal mass (measured: 1e-10 m/s)
  const double dv = (ls.velocities() - tr.velocities()).cwiseAbs().maxCoeff();
  CAPTURE(dv);
  CHECK(dv <= 2.0 * kResidual * std::sqrt(static_cast<double>(m.particle_count())));
}

TEST_CASE("trust-region converges on a buckling step and leaves the straight chain",
          "[trust-region]") {
  // a chain of 40 springs held at both ends, squeezed to 70 % of its length with a 0.1 mm
  // sideways kink, no gravity: the straight chain is a saddle of Phi (its compressed springs
  // give negative curvature sideways) and the step must buckle it
  constexpr int kLinks = 40;
  Scene s = clothbench::test::chain(kLinks, 0.01, 2000.0, 0.05, 0.0, 0.0);
  s.held[0] = kHoldAll;
  const Model m = build_model(s);
  Matrix3X x = m.x0;
  const double top = x(1, kLinks);
  for (Eigen::Index p = 0; p < x.cols(); ++p) {
    x(1, p) = top + 0.7 * (x(1, p) - top);
    x(0, p) = 1e-4 * std::sin(M_PI * static_cast<double>(p) / kLinks);
  }
  const Matrix3X rest = Matrix3X::Zero(3, m.particle_count());
  SolverOptions o = newton_options(NewtonMethod::trust_region);
  o.newton_iterations = 500;
  const MassSpringCloth c = one_step(s, o, x, rest);
  const std::vector<double>& phi = c.newton()->objective_history();
  CAPTURE(c.counters().newton_iterations, c.counters().cg_iterations, phi.front(), phi.back());
  CHECK(c.counters().newton_unconverged == 0);
  CHECK(c.newton()->last_residual() <= o.newton_tolerance * kStep);
  // buckled: particles moved sideways by far more than the kink (without bending stiffness any
  // shape with springs at rest length will do), at a lower Phi
  const double sideways = c.positions().topRows<1>().cwiseAbs().maxCoeff();
  CAPTURE(sideways);
  CHECK(sideways > 100.0 * 1e-4);
  CHECK(phi.back() < phi.front());
}

TEST_CASE("trust-region never raises the step's potential", "[trust-region]") {
  // the held fabric's first second at 1/30 s: every iterate is accepted only if Phi fell, so
  // the history never rises; rejected trials (Phi would have risen or fallen too little) must
  // occur, or the test would not exercise the acceptance test
  MassSpringCloth c(held_fabric(16), newton_options(NewtonMethod::trust_region));
  int rejected = 0, accepted = 0;
  for (int step = 0; step < 30; ++step) {
    c.step(kStep);
    const std::vector<double>& phi = c.newton()->objective_history();
    const std::vector<double>& res = c.newton()->residual_history();
    for (size_t i = 1; i < phi.size(); ++i) {
      CHECK(phi[i] <= phi[i - 1]);
      // an accepted step moved the iterate (its residual changed) and lowered Phi strictly
      if (res[i] != res[i - 1]) {
        CHECK(phi[i] < phi[i - 1]);
        ++accepted;
      } else {
        ++rejected;
      }
    }
  }
  CAPTURE(accepted, rejected);
  CHECK(rejected > 0);
  CHECK(accepted > 30);
}

TEST_CASE("trust-region converges quadratically near the solution of a convex step",
          "[trust-region]") {
  // a chain of 20 particles hanging from its top, pulled sideways by gravity at 60 degrees: its
  // springs all stretch, A is positive definite, and with tight linear solves the last
  // iterations must show Newton's quadratic convergence, r_{k+1} <= C r_k^2
  Scene s = clothbench::test::chain(20, 0.01, 2000.0, 0.05, 0.0, 9.8);
  s.gravity = 9.8 * Vector3(std::sin(1.0), -std::cos(1.0), 0.0);
  SolverOptions o = newton_options(NewtonMethod::trust_region);
  o.cg_forcing = CgForcing::fixed;
  o.cg_tolerance = 1e-14;
  o.newton_tolerance = 1e-11 / kStep;
  o.newton_iterations = 100;
  MassSpringCloth c(s, o);
  c.step(kStep);
  const std::vector<double>& r = c.newton()->residual_history();
  REQUIRE(r.back() <= 1e-11);
  // the ratios r_{k+1} / r_k^2 over the iterations that start below 1e-2 m/s (in the region of
  // quadratic convergence) and end above round-off
  double worst = 0.0;
  int counted = 0;
  for (size_t k = 0; k + 1 < r.size(); ++k) {
    if (r[k] > 1e-2 || r[k + 1] < 1e-13 || r[k + 1] == r[k]) continue;
    worst = std::max(worst, r[k + 1] / (r[k] * r[k]));
    ++counted;
  }
  CAPTURE(r, worst, counted);
  REQUIRE(counted >= 2);
  // measured 2.2 / (m/s); a linear rate q would give q / r_k, above 100 for any q > 1e-4 at the
  // last r_k (1.6e-6 m/s)
  CHECK(worst <= 100.0);
}

TEST_CASE("trust-region: a step after set_state is the first step of a run from that state",
          "[trust-region]") {
  // the region's radius carries from step to step; Simulator::set_state must start it afresh,
  // or a growth estimate's maps (set the state, step) would depend on the steps before them
  // (on 8 x 8 the first step's solves stay inside the region, whatever its radius)
  const Scene s = held_fabric(24);
  const SolverOptions o = newton_options(NewtonMethod::trust_region);
  MassSpringCloth fresh(s, o);
  const Matrix3X x0 = fresh.positions(), v0 = fresh.velocities();
  fresh.step(kStep);
  MassSpringCloth reused(s, o);
  for (int k = 0; k < 5; ++k) reused.step(kStep);
  reused.set_state(x0, v0, 0.0);
  reused.step(kStep);
  CHECK((reused.positions() - fresh.positions()).cwiseAbs().maxCoeff() == 0.0);
  CHECK((reused.velocities() - fresh.velocities()).cwiseAbs().maxCoeff() == 0.0);
}
