#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "cloth/analysis/linear_stability.hpp"
#include "cloth/forces/spring_forces.hpp"
#include "cloth/forces/spring_jacobians.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "cloth/model/model.hpp"
#include "test_scenes.hpp"
#include "tolerances.hpp"

using namespace cloth;
namespace tol = clothbench::tol;

namespace {

// an irregular spring network: random points in a unit cube, springs between random pairs at
// random rest lengths (none at rest) and stiffnesses, random velocities
struct Network {
  SpringSet springs;
  Matrix3X x, v;
};

Network random_network(unsigned seed, int points, int springs) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, points - 1);
  Network n;
  n.x = Matrix3X::NullaryExpr(3, points, [&]() { return u(rng); });
  n.v = Matrix3X::NullaryExpr(3, points, [&]() { return u(rng); });
  n.springs.damping = 0.7;
  const SpringKind kinds[] = {SpringKind::structural, SpringKind::shear, SpringKind::bend};
  for (int s = 0; s < springs; ++s) {
    const int a = pick(rng);
    int b = pick(rng);
    while (b == a) b = pick(rng);
    const double len = (n.x.col(b) - n.x.col(a)).norm();
    n.springs.list.push_back(
        {a, b, len * (1.0 + 0.4 * u(rng)), 500.0 + 400.0 * u(rng), kinds[s % 3]});
  }
  return n;
}

Matrix3X forces(const SpringSet& springs, const Matrix3X& x, const Matrix3X& v) {
  Matrix3X f = Matrix3X::Zero(3, x.cols()), buf(3, x.cols());
  add_spring_forces(springs, x, v, f, buf);
  return f;
}

// dense matrix of the product y = alpha K u + beta D u, column by column
Eigen::MatrixXd dense_jacobian(const SpringSet& springs, const Matrix3X& x, bool clamp,
                               double alpha, double beta) {
  const Eigen::Index n = x.cols();
  SpringLinearization lin;
  linearize_springs(springs, x, clamp, lin);
  Eigen::MatrixXd J(3 * n, 3 * n);
  Matrix3X u(3, n), y(3, n), buf(3, n);
  for (Eigen::Index c = 0; c < 3 * n; ++c) {
    u.setZero();
    u(c % 3, c / 3) = 1.0;
    y.setZero();
    add_jacobian_product(springs, lin, u, alpha, beta, y, buf);
    for (Eigen::Index r = 0; r < 3 * n; ++r) J(r, c) = y(r % 3, r / 3);
  }
  return J;
}

// central differences of the forces in x (velocities v) or in v (positions x)
Eigen::MatrixXd finite_difference(const SpringSet& springs, const Matrix3X& x, const Matrix3X& v,
                                  bool in_velocity) {
  const Eigen::Index n = x.cols();
  const double step = 1e-6;
  Eigen::MatrixXd J(3 * n, 3 * n);
  for (Eigen::Index c = 0; c < 3 * n; ++c) {
    Matrix3X xp = x, xm = x, vp = v, vm = v;
    (in_velocity ? vp : xp)(c % 3, c / 3) += step;
    (in_velocity ? vm : xm)(c % 3, c / 3) -= step;
    const Matrix3X df = (forces(springs, xp, vp) - forces(springs, xm, vm)) / (2 * step);
    for (Eigen::Index r = 0; r < 3 * n; ++r) J(r, c) = df(r % 3, r / 3);
  }
  return J;
}

// the trajectory scene: a 7 x 6 cloth under gravity, held at two corners, falling onto a
// sphere, with spring damping, air drag and unequal stiffnesses
Scene draped_scene() {
  Scene s = clothbench::test::small_cloth(7, 300.0, 0.8);
  s.cloth.nv = 6;
  s.cloth.k_shear = 120.0;
  s.cloth.k_bend = 40.0;
  s.held.assign(size_t(7 * 6), 0);
  s.held[0] = s.held[6] = kHoldAll;
  s.gravity = {0.0, -9.8, 0.0};
  s.cloth.air_drag = 0.02;
  Sphere ball;
  ball.center = {0.1, -0.45, 0.45};
  ball.radius = 0.3;
  ball.friction = 0.2;
  s.spheres.push_back(ball);
  return s;
}

// one configuration per integrator; implicit Euler in both Newton modes, line search with an
// iterative and the direct linear solver
struct Config {
  std::string name;
  SolverOptions options;
};

std::vector<Config> all_configs() {
  std::vector<Config> out;
  for (Integrator i : all_integrators()) {
    SolverOptions o;
    o.integrator = i;
    out.push_back({integrator_name(i), o});
    if (i != Integrator::implicit_euler) continue;
    out.push_back({"implicit-euler line-search", line_search_options(LinearSolver::automatic)});
    out.push_back({"implicit-euler line-search ldlt", line_search_options(LinearSolver::ldlt)});
  }
  return out;
}

// largest |i - j| over the springs
int bandwidth(const std::vector<SpringLink>& links) {
  int w = 0;
  for (const SpringLink& l : links) w = std::max(w, std::abs(l.a - l.b));
  return w;
}

}  // namespace

TEST_CASE("to_general keeps every spring in the order of links()", "[springs]") {
  const Model m = build_model(draped_scene());
  const SpringSet g = to_general(m.springs);
  CHECK(g.families.empty());
  CHECK(g.count() == m.springs.count());
  CHECK(g.damping == m.springs.damping);
  const std::vector<SpringLink> a = m.springs.links(), b = g.links();
  REQUIRE(a.size() == b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].a == b[i].a);
    CHECK(a[i].b == b[i].b);
    CHECK(a[i].rest == b[i].rest);
    CHECK(a[i].stiffness == b[i].stiffness);
    CHECK(a[i].kind == b[i].kind);
  }
}

TEST_CASE("the general path reproduces the grid kernel's trajectory in every integrator",
          "[springs]") {
  const Config config = GENERATE(from_range(all_configs()));
  CAPTURE(config.name);
  const Scene scene = draped_scene();
  Model general = build_model(scene);
  general.springs = to_general(general.springs);
  MassSpringCloth grid(scene, config.options), list(general, config.options);
  const double h = 1e-3;
  double largest = 0.0;
  int touching = 0;
  for (int i = 0; i < 600; ++i) {
    grid.step(h);
    list.step(h);
    largest = std::max(largest, (grid.positions() - list.positions()).cwiseAbs().maxCoeff());
    touching += grid.contacts() > 0 ? 1 : 0;
  }
  const double moved = (grid.positions() - grid.model().x0).cwiseAbs().maxCoeff();
  CHECK(touching > 0);  // the cloth meets the sphere: contact is part of the run
  CHECK(moved > 0.3);
  CHECK(largest <= tol::kGeneralPathTrajectory);
  CHECK(std::abs(grid.dissipated() - list.dissipated()) <=
        tol::kGeneralPathRelative * grid.dissipated());
}

TEST_CASE("two-level-cg refuses a general spring list and names the solver to use", "[springs]") {
  Model general = build_model(draped_scene());
  general.springs = to_general(general.springs);
  try {
    MassSpringCloth c(general, line_search_options(LinearSolver::two_level_cg));
    FAIL("no exception");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("block-jacobi-cg") != std::string::npos);
  }
  // auto never chooses it for a general list, however large
  CHECK(resolved_linear_solver(LinearSolver::automatic, 100000, false) ==
        LinearSolver::block_jacobi_cg);
  CHECK(resolved_linear_solver(LinearSolver::automatic, 100000, true) ==
        LinearSolver::two_level_cg);
}

TEST_CASE("internal forces of a random spring network have zero sum and zero torque", "[springs]") {
  const unsigned seed = GENERATE(11u, 12u, 13u);
  const Network n = random_network(seed, 40, 150);
  const Matrix3X f = forces(n.springs, n.x, n.v);
  CHECK(f.norm() > 1.0);  // the springs really are loaded
  Vector3 torque = Vector3::Zero();
  for (Eigen::Index p = 0; p < f.cols(); ++p)
    torque += Vector3(n.x.col(p)).cross(Vector3(f.col(p)));
  CHECK(Vector3(f.rowwise().sum()).norm() < tol::kForceBalance);
  CHECK(torque.norm() < tol::kForceBalance);
  // the power the kernel reports is the dampers' (forces with and without damping)
  SpringSet undamped = n.springs;
  undamped.damping = 0.0;
  const Matrix3X fd = f - forces(undamped, n.x, n.v);
  Matrix3X g = Matrix3X::Zero(3, f.cols()), buf = g;
  const double reported = add_spring_forces(n.springs, n.x, n.v, g, buf);
  CHECK(reported == Approx(-(fd.array() * n.v.array()).sum()).epsilon(1e-12));
  CHECK(damping_power(n.springs, n.x, n.v) == Approx(reported).epsilon(1e-12));
}

TEST_CASE("a free random spring network keeps its momentum and angular momentum", "[springs]") {
  // symplectic Euler conserves both exactly for central internal forces: L changes by
  // h sum x x f, which is zero
  const Network n = random_network(14, 30, 100);
  Model m;
  m.x0 = n.x;
  m.mass = VectorX::LinSpaced(n.x.cols(), 0.05, 0.15);
  m.inv_mass = m.mass.cwiseInverse();
  m.free = Matrix3X::Ones(3, n.x.cols());
  m.springs = n.springs;
  SolverOptions o;
  o.integrator = Integrator::symplectic_euler;
  MassSpringCloth c(m, o);
  c.set_state(n.x, n.v);
  auto momentum = [&]() { return Vector3(c.velocities() * m.mass); };
  auto angular = [&]() {
    Vector3 l = Vector3::Zero();
    for (Eigen::Index p = 0; p < n.x.cols(); ++p)
      l += m.mass[p] * Vector3(c.positions().col(p)).cross(Vector3(c.velocities().col(p)));
    return l;
  };
  const Vector3 p0 = momentum(), l0 = angular();
  const Matrix3X v0 = c.velocities();
  for (int i = 0; i < 500; ++i) c.step(1e-4);
  CHECK((c.velocities() - v0).norm() > 1.0);  // the springs changed the motion
  CHECK((momentum() - p0).norm() < tol::kMomentumDrift);
  CHECK((angular() - l0).norm() < tol::kMomentumDrift);
}

TEST_CASE("general-list Jacobians match central differences", "[springs]") {
  const unsigned seed = GENERATE(15u, 16u);
  const Network n = random_network(seed, 12, 40);
  const Matrix3X zero_v = Matrix3X::Zero(3, n.x.cols());  // no damping force x-derivative
  const Eigen::MatrixXd K = dense_jacobian(n.springs, n.x, false, 1.0, 0.0);
  const Eigen::MatrixXd K_fd = finite_difference(n.springs, n.x, zero_v, false);
  CHECK((K - K_fd).norm() <= tol::kJacobianRelative * K.norm());
  CHECK((K - K.transpose()).norm() <= 1e-12 * K.norm());
  const Eigen::MatrixXd D = dense_jacobian(n.springs, n.x, false, 0.0, 1.0);
  const Eigen::MatrixXd D_fd = finite_difference(n.springs, n.x, n.v, true);
  CHECK(D.norm() > 0.0);
  CHECK((D - D_fd).norm() <= tol::kJacobianRelative * D.norm());
  // the diagonal and the one-pass Newton product agree with the dense products
  const double alpha = -0.3, beta = -0.7;
  const Eigen::MatrixXd A = dense_jacobian(n.springs, n.x, true, alpha, beta);
  SpringLinearization lin, lin_d;
  linearize_springs(n.springs, n.x, true, lin);
  Matrix3X diag = Matrix3X::Zero(3, n.x.cols()), buf = diag;
  add_jacobian_diagonal(n.springs, lin, alpha, beta, diag, buf);
  for (Eigen::Index c = 0; c < 3 * n.x.cols(); ++c)
    CHECK(diag(c % 3, c / 3) == Approx(A(c, c)).epsilon(1e-12));
  linearize_springs(n.springs, n.x + 0.1 * n.v, true, lin_d);
  Matrix3X fused = Matrix3X::Zero(3, n.x.cols()), split = fused;
  add_newton_product(n.springs, lin, lin_d, n.v, alpha, beta, fused, buf);
  add_jacobian_product(n.springs, lin, n.v, alpha, 0.0, split, buf);
  add_jacobian_product(n.springs, lin_d, n.v, 0.0, beta, split, buf);
  CHECK(fused.norm() > 0.0);
  CHECK((fused - split).norm() <= 1e-13 * split.norm());
}

TEST_CASE("a grid and its general copy have the same Jacobians and energies", "[springs]") {
  const Model m = build_model(draped_scene());
  const SpringSet g = to_general(m.springs);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  const Matrix3X x = m.x0 + Matrix3X::NullaryExpr(3, m.x0.cols(), [&]() { return u(rng); });
  for (const bool clamp : {false, true}) {
    const Eigen::MatrixXd a = dense_jacobian(m.springs, x, clamp, -0.3, -0.7);
    CHECK((a - dense_jacobian(g, x, clamp, -0.3, -0.7)).norm() <=
          tol::kGeneralPathRelative * a.norm());
  }
  CHECK(elastic_energy(g, x) == Approx(elastic_energy(m.springs, x)).epsilon(1e-13));
  CHECK(within_strain(g, x, 0.2) == within_strain(m.springs, x, 0.2));
  const StrainStats a = strain_stats(m.springs, x), b = strain_stats(g, x);
  CHECK(a.max_abs == b.max_abs);
  CHECK(a.max_stretch == b.max_stretch);
  CHECK(a.max_compression == b.max_compression);
  CHECK(a.mean_abs == Approx(b.mean_abs).epsilon(1e-14));
}

TEST_CASE("stretch and compression leave out bend springs", "[springs]") {
  // a triangle: structural spring 0-1 (rest 1 m) at 1.25 m, shear spring 2-1 (rest 1 m) at
  // 0.6 m, bend spring 0-2 (rest 2 m) folded to 0.7 m, the largest |strain|
  SpringSet s;
  s.list.push_back({0, 1, 1.0, 10.0, SpringKind::structural});
  s.list.push_back({2, 1, 1.0, 10.0, SpringKind::shear});
  s.list.push_back({0, 2, 2.0, 10.0, SpringKind::bend});
  Matrix3X x = Matrix3X::Zero(3, 3);
  x.col(2) << 0.7, 0.0, 0.0;
  const double px = (1.25 * 1.25 - 0.6 * 0.6 + 0.7 * 0.7) / (2 * 0.7);
  x.col(1) << px, std::sqrt(1.25 * 1.25 - px * px), 0.0;
  REQUIRE((x.col(1) - x.col(0)).norm() == Approx(1.25).epsilon(1e-14));
  REQUIRE((x.col(1) - x.col(2)).norm() == Approx(0.6).epsilon(1e-14));
  const StrainStats st = strain_stats(s, x);
  CHECK(st.max_stretch == Approx(0.25).epsilon(1e-13));
  CHECK(st.max_compression == Approx(0.4).epsilon(1e-13));
  CHECK(st.max_abs == Approx(0.65).epsilon(1e-13));  // the bend spring: 0.7 / 2 - 1
  CHECK(st.mean_abs == Approx((0.25 + 0.4 + 0.65) / 3).epsilon(1e-13));
  // doubled: both surface springs stretched, the bend spring still compressed but not counted
  const StrainStats grown = strain_stats(s, 2.0 * x);
  CHECK(grown.max_stretch == Approx(1.5).epsilon(1e-13));
  CHECK(grown.max_compression == 0.0);
  // halved: both compressed, none stretched
  const StrainStats shrunk = strain_stats(s, 0.5 * x);
  CHECK(shrunk.max_stretch == 0.0);
  CHECK(shrunk.max_compression == Approx(0.7).epsilon(1e-13));  // 1 - 0.5 * 0.6
  // a NaN anywhere makes every statistic NaN
  x(0, 1) = std::numeric_limits<double>::quiet_NaN();
  const StrainStats bad = strain_stats(s, x);
  CHECK(std::isnan(bad.max_abs));
  CHECK(std::isnan(bad.mean_abs));
  CHECK(std::isnan(bad.max_stretch));
  CHECK(std::isnan(bad.max_compression));
}

TEST_CASE("locality_order is a permutation that undoes a shuffle's bandwidth", "[springs]") {
  Scene s = clothbench::test::small_cloth(16);
  s.cloth.nv = 11;
  s.held.assign(size_t(16 * 11), 0);
  const Model m = build_model(s);
  const int n = m.particle_count();
  std::vector<int> shuffle(static_cast<size_t>(n));
  std::iota(shuffle.begin(), shuffle.end(), 0);
  std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937(18));
  const SpringSet shuffled = renumbered(m.springs, shuffle);
  const std::vector<int> order = locality_order(n, shuffled.links());
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> identity(static_cast<size_t>(n));
  std::iota(identity.begin(), identity.end(), 0);
  CHECK(sorted == identity);
  CHECK(order == locality_order(n, shuffled.links()));  // deterministic
  const int grid = bandwidth(m.springs.links()), mixed = bandwidth(shuffled.links());
  const int ordered = bandwidth(renumbered(shuffled, order).links());
  CAPTURE(grid, mixed, ordered);
  CHECK(mixed > n / 2);
  // RCM's bandwidth is that of a level structure: about two levels' width on a grid with
  // bend springs, here no worse than the grid's own numbering's
  CHECK(ordered <= grid);
  // isolated particles and several components still give a permutation
  std::vector<SpringLink> two = {{0, 3, 1, 1, SpringKind::structural},
                                 {5, 4, 1, 1, SpringKind::structural}};
  std::vector<int> o2 = locality_order(7, two);
  std::sort(o2.begin(), o2.end());
  CHECK(o2 == std::vector<int>{0, 1, 2, 3, 4, 5, 6});
}

TEST_CASE("the stability predictor gives a grid and its general copy the same limits",
          "[springs][stability][.heavy]") {
  // equal stiffnesses (damping exactly proportional) and unequal ones (dense modal analysis)
  const double shear = GENERATE(300.0, 120.0);
  Scene s = draped_scene();
  s.cloth.k_shear = shear;
  s.cloth.k_bend = shear == 300.0 ? 300.0 : 40.0;
  s.spheres.clear();
  const Model grid = build_model(s);
  Model general = grid;
  general.springs = to_general(grid.springs);
  const LinearSpectrum a = linear_spectrum(grid), b = linear_spectrum(general);
  CHECK(a.exact == b.exact);
  CHECK(a.exact == (shear == 300.0));
  CHECK(b.omega_max == Approx(a.omega_max).epsilon(tol::kGeneralPathRelative));
  CHECK(b.beta == Approx(a.beta).epsilon(tol::kGeneralPathRelative));
  for (Integrator i : all_integrators()) {
    CAPTURE(integrator_name(i));
    const double ha = predicted_stable_dt(i, a), hb = predicted_stable_dt(i, b);
    if (std::isinf(ha)) {
      CHECK(std::isinf(hb));
      continue;
    }
    CHECK(hb == Approx(ha).epsilon(tol::kGeneralPathRelative));
  }
}
