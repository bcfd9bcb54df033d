#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <random>

#include "cloth/forces/spring_forces.hpp"
#include "cloth/forces/spring_jacobians.hpp"
#include "cloth/model/model.hpp"
#include "test_scenes.hpp"
#include "tolerances.hpp"

using namespace cloth;
namespace tol = clothbench::tol;

namespace {

// a 6 x 5 grid with every spring kind, shaken randomly so no spring is at rest
struct Shaken {
  Model model;
  Matrix3X x, v;
};

Shaken shaken_grid(unsigned seed, double amplitude) {
  Scene s = clothbench::test::small_cloth(5, 1000.0, 3.0);
  s.cloth.nu = 6;
  s.held.clear();
  Shaken out{build_model(s), {}, {}};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  out.x = out.model.x0;
  out.v = Matrix3X::Zero(3, out.x.cols());
  for (Eigen::Index p = 0; p < out.x.cols(); ++p)
    for (int r = 0; r < 3; ++r) {
      out.x(r, p) += amplitude * u(rng);
      out.v(r, p) = u(rng);
    }
  return out;
}

Matrix3X forces(const Model& m, const Matrix3X& x, const Matrix3X& v) {
  Matrix3X f = Matrix3X::Zero(3, x.cols()), buf(3, x.cols());
  add_spring_forces(m.springs, x, v, f, buf);
  return f;
}

// dense matrix of the product y = alpha K u + beta D u, column by column
Eigen::MatrixXd dense_jacobian(const Model& m, const Matrix3X& x, bool clamp, double alpha,
                               double beta) {
  const Eigen::Index n = x.cols();
  SpringLinearization lin;
  linearize_springs(m.springs, x, clamp, lin);
  Eigen::MatrixXd J(3 * n, 3 * n);
  Matrix3X u(3, n), y(3, n), buf(3, n);
  for (Eigen::Index c = 0; c < 3 * n; ++c) {
    u.setZero();
    u(c % 3, c / 3) = 1.0;
    y.setZero();
    add_jacobian_product(m.springs, lin, u, alpha, beta, y, buf);
    for (Eigen::Index rr = 0; rr < 3 * n; ++rr) J(rr, c) = y(rr % 3, rr / 3);
  }
  return J;
}

}  // namespace

TEST_CASE("grid has the expected spring counts", "[springs]") {
  Scene s = clothbench::test::small_cloth(5);
  s.cloth.nu = 6;
  s.held.clear();
  const Model m = build_model(s);
  // structural (nu-1) nv + nu (nv-1); shear 2 (nu-1)(nv-1); bend (nu-2) nv + nu (nv-2)
  const int nu = 6, nv = 5;
  CHECK(m.springs.count() ==
        (nu - 1) * nv + nu * (nv - 1) + 2 * (nu - 1) * (nv - 1) + (nu - 2) * nv + nu * (nv - 2));
  // a kind with stiffness 0 creates no springs
  s.cloth.k_bend = 0.0;
  CHECK(build_model(s).springs.count() == (nu - 1) * nv + nu * (nv - 1) + 2 * (nu - 1) * (nv - 1));
  // links agree with the families and join grid neighbours at their rest distance
  for (const SpringLink& l : m.springs.links()) {
    const int di = l.b % nu - l.a % nu, dj = l.b / nu - l.a / nu;
    CHECK(std::abs(di) <= 2);
    CHECK(dj >= 0);
    CHECK(l.rest == Approx((m.x0.col(l.b) - m.x0.col(l.a)).norm()));
  }
}

TEST_CASE("internal forces sum to zero force and zero torque", "[springs]") {
  const unsigned seed = GENERATE(1u, 2u, 3u);
  const Shaken g = shaken_grid(seed, 0.05);
  const Matrix3X f = forces(g.model, g.x, g.v);
  CHECK(f.norm() > 1.0);  // the springs really are loaded
  const Vector3 total = f.rowwise().sum();
  Vector3 torque = Vector3::Zero();
  for (Eigen::Index p = 0; p < f.cols(); ++p)
    torque += Vector3(g.x.col(p)).cross(Vector3(f.col(p)));
  CHECK(total.norm() < tol::kForceBalance);
  CHECK(torque.norm() < tol::kForceBalance);
}

TEST_CASE("damping power equals minus the damping forces' power", "[springs]") {
  const Shaken g = shaken_grid(4, 0.05);
  Model undamped = g.model;
  undamped.springs.damping = 0.0;
  const Matrix3X fd = forces(g.model, g.x, g.v) - forces(undamped, g.x, g.v);
  const double power_of_forces = (fd.array() * g.v.array()).sum();
  Matrix3X f = Matrix3X::Zero(3, g.x.cols()), buf = f;
  const double reported = add_spring_forces(g.model.springs, g.x, g.v, f, buf);
  CHECK(reported > 0.0);
  CHECK(reported == Approx(-power_of_forces).epsilon(1e-12));
  CHECK(damping_power(g.model.springs, g.x, g.v) == Approx(reported).epsilon(1e-12));
}

TEST_CASE("spring stiffness Jacobian matches central differences", "[springs]") {
  const unsigned seed = GENERATE(5u, 6u);
  const Shaken g = shaken_grid(seed, 0.05);
  const Matrix3X zero_v =
      Matrix3X::Zero(3, g.x.cols());  // the damping force then has no x-derivative
  const Eigen::Index n = g.x.cols();
  const Eigen::MatrixXd K = dense_jacobian(g.model, g.x, false, 1.0, 0.0);
  const double step = 1e-6;
  Eigen::MatrixXd K_fd(3 * n, 3 * n);
  for (Eigen::Index c = 0; c < 3 * n; ++c) {
    Matrix3X xp = g.x, xm = g.x;
    xp(c % 3, c / 3) += step;
    xm(c % 3, c / 3) -= step;
    const Matrix3X df = (forces(g.model, xp, zero_v) - forces(g.model, xm, zero_v)) / (2 * step);
    for (Eigen::Index r = 0; r < 3 * n; ++r) K_fd(r, c) = df(r % 3, r / 3);
  }
  CHECK((K - K_fd).norm() <= tol::kJacobianRelative * K.norm());
  // symmetric, as the Hessian of the elastic energy
  CHECK((K - K.transpose()).norm() <= 1e-12 * K.norm());
}

TEST_CASE("spring damping Jacobian matches central differences", "[springs]") {
  const Shaken g = shaken_grid(7, 0.05);
  const Eigen::Index n = g.x.cols();
  const Eigen::MatrixXd D = dense_jacobian(g.model, g.x, false, 0.0, 1.0);
  const double step = 1e-6;
  Eigen::MatrixXd D_fd(3 * n, 3 * n);
  for (Eigen::Index c = 0; c < 3 * n; ++c) {
    Matrix3X vp = g.v, vm = g.v;
    vp(c % 3, c / 3) += step;
    vm(c % 3, c / 3) -= step;
    const Matrix3X df = (forces(g.model, g.x, vp) - forces(g.model, g.x, vm)) / (2 * step);
    for (Eigen::Index r = 0; r < 3 * n; ++r) D_fd(r, c) = df(r % 3, r / 3);
  }
  CHECK(D.norm() > 0.0);
  CHECK((D - D_fd).norm() <= tol::kJacobianRelative * D.norm());
}

TEST_CASE("clamped stiffness is negative semidefinite, the unclamped one is not", "[springs]") {
  // every spring compressed: transverse stiffness of the exact Jacobian is destabilising
  Scene s = clothbench::test::small_cloth(4, 1000.0, 0.0);
  s.held.clear();
  const Model m = build_model(s);
  const Matrix3X x = 0.8 * m.x0;  // uniform compression to 80%
  const Eigen::MatrixXd K_exact = dense_jacobian(m, x, false, 1.0, 0.0);
  const Eigen::MatrixXd K_clamped = dense_jacobian(m, x, true, 1.0, 0.0);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> exact(K_exact), clamped(K_clamped);
  CHECK(exact.eigenvalues().maxCoeff() > 1.0);
  CHECK(clamped.eigenvalues().maxCoeff() < 1e-9 * K_clamped.norm());
  // when every spring is stretched the clamp changes nothing
  const Matrix3X stretched = 1.1 * m.x0;
  CHECK(
      (dense_jacobian(m, stretched, false, 1.0, 0.0) - dense_jacobian(m, stretched, true, 1.0, 0.0))
          .norm() == 0.0);
}

TEST_CASE("Jacobian diagonal matches the dense matrix", "[springs]") {
  const Shaken g = shaken_grid(8, 0.05);
  const Eigen::Index n = g.x.cols();
  const double alpha = -0.3, beta = -0.7;
  const Eigen::MatrixXd A = dense_jacobian(g.model, g.x, true, alpha, beta);
  SpringLinearization lin;
  linearize_springs(g.model.springs, g.x, true, lin);
  Matrix3X diag = Matrix3X::Zero(3, n), buf(3, n);
  add_jacobian_diagonal(g.model.springs, lin, alpha, beta, diag, buf);
  for (Eigen::Index c = 0; c < 3 * n; ++c)
    CHECK(diag(c % 3, c / 3) == Approx(A(c, c)).epsilon(1e-12));
}

TEST_CASE("the one-pass Newton product equals the stiffness and damping products", "[springs]") {
  // K at one shaken state, D's directions at another, as in a Newton iteration of a step
  const Shaken g = shaken_grid(9, 0.05), start = shaken_grid(10, 0.05);
  const Eigen::Index n = g.x.cols();
  SpringLinearization lin_k, lin_d;
  linearize_springs(g.model.springs, g.x, true, lin_k);
  linearize_springs(g.model.springs, start.x, true, lin_d);
  const double alpha = -1.1e-3, beta = -3.3e-2;  // -h^2 and -h at h = 1/30 s
  Matrix3X fused = g.v, split = g.v, buf(3, n);
  add_newton_product(g.model.springs, lin_k, lin_d, start.v, alpha, beta, fused, buf);
  add_jacobian_product(g.model.springs, lin_k, start.v, alpha, 0.0, split, buf);
  add_jacobian_product(g.model.springs, lin_d, start.v, 0.0, beta, split, buf);
  CHECK((fused - g.v).norm() > 0.0);
  CHECK((fused - split).norm() <= 1e-13 * (split - g.v).norm());
}

TEST_CASE("the blow-up test reads stretch: a fold is no blow-up, an overstretched edge is",
          "[springs]") {
  // a 5 x 1 strip along x, 1 m spacing: structural springs 1 m, bend springs 2 m
  Scene s = clothbench::test::small_cloth(5, 100.0, 0.0);
  s.cloth.nv = 1;
  s.cloth.size_u = 4.0;
  s.held.clear();
  const Model m = build_model(s);
  Matrix3X x = m.x0;
  SECTION("folded in half: the bend spring across the fold closes to nearly nothing") {
    // particles 3 and 4 folded back over 1 and 2, 1 mm above them
    x.col(3) = m.x0.col(1) + Vector3(0, 1e-3, 0);
    x.col(4) = m.x0.col(0) + Vector3(0, 1e-3, 0);
    // the bend spring 2-4 now spans 2 m -> 2 m, 1-3 spans 1e-3 m of its 2 m: |strain| ~ 1
    CHECK_FALSE(within_strain(m.springs, x, 0.9));
    CHECK(within_stretch(m.springs, x, 0.9));
    const StrainStats st = strain_stats(m.springs, x);
    CHECK(st.max_abs == Approx(1.0 - 1e-3 / 2.0));
    CHECK(st.max_stretch < 1e-6);
  }
  SECTION("one structural spring stretched to 2.5 times its length") {
    x.col(4).x() += 1.5;
    CHECK_FALSE(within_stretch(m.springs, x, 1.0));
    CHECK(within_stretch(m.springs, x, 1.6));
    CHECK(strain_stats(m.springs, x).max_stretch == Approx(1.5));
  }
  SECTION("a non-finite coordinate fails") {
    x(1, 2) = std::numeric_limits<double>::quiet_NaN();
    CHECK_FALSE(within_stretch(m.springs, x, 1.0));
  }
}
