#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <cmath>

#include "cloth/integrators/mass_spring_cloth.hpp"
#include "cloth/solvers/coarse_grid.hpp"
#include "cloth/solvers/implicit_matrix.hpp"
#include "test_scenes.hpp"

using namespace cloth;

namespace {

constexpr double kFrame = 1.0 / 30.0;  // s

/// A 19 x 11 seed cloth with drag, an edge particle held in y besides the seed's holds, and
/// shaken positions, so that springs are stretched and compressed in every direction.
struct ShakenCloth {
  Model m;
  Matrix3X x, x0;
  ShakenCloth() {
    Scene s = seed_scene(8);
    s.cloth.nu = 19;
    s.cloth.nv = 11;
    s.held.assign(19 * 11, 0);
    for (int p : {0, 18, 190, 208}) s.held[p] = kHoldAll;
    s.held[3] = kHoldY;
    s.cloth.air_drag = 0.3;
    m = build_model(s);
    x = m.x0;
    x0 = m.x0;
    for (Eigen::Index p = 0; p < x.cols(); ++p) {
      x.col(p) += 0.05 * Vector3(std::sin(3.0 * p), std::cos(5.0 * p), std::sin(7.0 * p + 1));
      x0.col(p) += 0.05 * Vector3(std::cos(2.0 * p), std::sin(p), std::cos(11.0 * p));
    }
  }
};

}  // namespace

TEST_CASE("the coarse grid interpolates constants and linear fields exactly", "[integrator]") {
  const int coarsening = GENERATE(2, 3, 8, 40);
  CAPTURE(coarsening);
  const ShakenCloth c;
  const CoarseGrid g(c.m, coarsening);
  // a field a + b i + c j of the grid indices, set on the coarse nodes at their grid positions,
  // comes back the same on every particle; intervals of at most `coarsening` particles along 19 and
  // 11 particles
  const int cu = (18 + coarsening - 1) / coarsening + 1,
            cv = (10 + coarsening - 1) / coarsening + 1;
  REQUIRE(cu * cv == g.nodes());
  Eigen::VectorXd coarse(3 * g.nodes());
  for (int l = 0; l < cv; ++l)
    for (int k = 0; k < cu; ++k) {
      const double i = 18.0 * k / (cu - 1), j = 10.0 * l / (cv - 1);
      coarse.segment<3>(3 * (l * cu + k)) = Vector3(1.0, 2.0 + 0.5 * i, -1.0 + 0.25 * j - 0.1 * i);
    }
  const Eigen::VectorXd fine = g.prolongation() * coarse;
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 19; ++i) {
      CAPTURE(i, j);
      const Vector3 expected(1.0, 2.0 + 0.5 * i, -1.0 + 0.25 * j - 0.1 * i);
      CHECK((fine.segment<3>(3 * (j * 19 + i)) - expected).norm() <= 1e-12);
    }
}

TEST_CASE("the coarse matrix is P^T A P of the filtered Newton matrix", "[integrator]") {
  const int coarsening = GENERATE(2, 4, 8);
  CAPTURE(coarsening);
  const ShakenCloth c;
  const Model& m = c.m;
  SpringLinearization lin_k, lin_d;
  linearize_springs(m.springs, c.x, true, lin_k);
  linearize_springs(m.springs, c.x0, true, lin_d);
  // contacts on free particles, with normals off the axes
  std::vector<ContactConstraint> contacts;
  for (int p : {40, 41, 100, 150}) {
    REQUIRE(m.free.col(p).minCoeff() == 1.0);
    contacts.push_back({p, Vector3(0.3, 1.0, -0.2 * p / 100.0).normalized(), 0.1});
  }
  ImplicitMatrix a(m);
  a.assemble(m, lin_k, lin_d, kFrame);
  a.apply_contacts(m, contacts, true);
  CoarseGrid g(m, coarsening);
  g.build(m, lin_k, lin_d, kFrame, contacts);
  REQUIRE(g.ok());
  const Eigen::SparseMatrix<double> p = g.prolongation();
  const Eigen::MatrixXd expected = Eigen::MatrixXd(p.transpose() * a.matrix() * p);
  const Eigen::MatrixXd built(g.matrix());
  CHECK((built - expected).cwiseAbs().maxCoeff() <= 1e-11 * expected.cwiseAbs().maxCoeff());
  // and the correction is P A_c^-1 P^T r
  Matrix3X r(3, m.particle_count()), z = Matrix3X::Zero(3, m.particle_count());
  for (Eigen::Index q = 0; q < r.cols(); ++q)
    r.col(q) = Vector3(std::sin(q), std::cos(2.0 * q), 1.0);
  g.add_correction(r, z);
  Eigen::VectorXd r_interleaved(3 * r.cols()), z_interleaved(3 * r.cols());
  for (Eigen::Index q = 0; q < r.cols(); ++q) {
    r_interleaved.segment<3>(3 * q) = r.col(q);
    z_interleaved.segment<3>(3 * q) = z.col(q);
  }
  const Eigen::VectorXd z_expected = p * expected.ldlt().solve(p.transpose() * r_interleaved);
  CHECK((z_interleaved - z_expected).norm() <= 1e-9 * z_expected.norm());
}

TEST_CASE("the coarse correction cuts the CG iterations of the 64 x 64 seed scene",
          "[integrator]") {
  // block-Jacobi needs more CG iterations per Newton system as the grid is refined (the
  // README's exponent); the coarse grid carries the smooth part of the error that takes them
  auto cg_per_newton = [](LinearSolver solver) {
    MassSpringCloth c(seed_scene(64), line_search_options(solver));
    for (int step = 0; step < 9; ++step) c.step(kFrame);
    return double(c.counters().cg_iterations) / double(c.counters().newton_iterations);
  };
  const double blocks = cg_per_newton(LinearSolver::block_jacobi_cg);
  const double two_level = cg_per_newton(LinearSolver::two_level_cg);
  CAPTURE(blocks, two_level);
  CHECK(two_level < 0.5 * blocks);
}
