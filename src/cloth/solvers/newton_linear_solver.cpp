#include "cloth/solvers/newton_linear_solver.hpp"

namespace cloth {

namespace {

using Interleaved = Eigen::Matrix<double, 3, Eigen::Dynamic>;  // column-major: 3 p + r

}  // namespace

NewtonLinearSolver::NewtonLinearSolver(const Model& m, LinearSolver solver) : m_solver(solver) {
  const Eigen::Index n = m.particle_count();
  m_inv_diag.setZero(3, n);
  m_buf.setZero(3, n);
  m_cg.resize(n);
  m_b.setZero(3 * n);
  m_x.setZero(3 * n);
  if (solver == LinearSolver::two_level_cg) m_coarse = std::make_unique<CoarseGrid>(m, kCoarsening);
}

CgResult NewtonLinearSolver::solve(const Model& m, const ImplicitMatrix& a,
                                   const SpringLinearization& lin_k,
                                   const SpringLinearization& lin_a,
                                   const SpringLinearization& lin_d, double h, const Matrix3X& b,
                                   Matrix3X& x, double tolerance, int max_iterations,
                                   const std::vector<ContactConstraint>& contacts, bool truncate) {
  if (m_solver != LinearSolver::ldlt)
    return solve_cg(m, a, lin_k, lin_a, lin_d, h, b, x, tolerance, max_iterations, contacts,
                    truncate);
  // the pattern is fixed, so the ordering and elimination tree are computed once
  if (!m_analyzed) {
    m_ldlt.analyzePattern(a.matrix());
    m_analyzed = true;
  }
  m_ldlt.factorize(a.matrix());
  m_ok = m_ldlt.info() == Eigen::Success;
  Eigen::Map<Interleaved>(m_b.data(), 3, b.cols()) = b;
  m_x = m_ldlt.solve(m_b);
  x = Eigen::Map<const Interleaved>(m_x.data(), 3, b.cols());
  return {};
}

template <class Run>
auto NewtonLinearSolver::with_operators(const Model& m, const ImplicitMatrix& a,
                                        const SpringLinearization& lin_k,
                                        const SpringLinearization& lin_a,
                                        const SpringLinearization& lin_d, double h,
                                        const std::vector<ContactConstraint>& contacts, Run&& run) {
  // A u = (M + h drag) u - h^2 K u - h D0 u, matrix-free
  auto apply = [&](const Matrix3X& u, Matrix3X& out) {
    for (int r = 0; r < 3; ++r)
      out.row(r) = u.row(r).cwiseProduct(m.mass.transpose()) + (h * m.air_drag) * u.row(r);
    add_newton_product(m.springs, lin_k, lin_d, u, -h * h, -h, out, m_buf);
    a.add_particle_block_product(u, out);
  };
  // S: the held-axis mask, then I - n n^T at each contact
  auto project = [&](Matrix3X& u) {
    u.array() *= m.free.array();
    remove_normal_parts(contacts, u);
  };
  if (m_solver == LinearSolver::block_jacobi_cg || m_solver == LinearSolver::two_level_cg) {
    // z_p = B_p^-1 r_p with B_p particle p's 3 by 3 diagonal block (identity rows when held)
    a.diagonal_block_inverses(m_block_inv);
    // row by row over the particles, so that it vectorises
    auto blocks = [&](const Matrix3X& r, Matrix3X& z) {
      const ImplicitMatrix::SymmetricRows& inv = m_block_inv;
      z.row(0) = inv.row(0).cwiseProduct(r.row(0)) + inv.row(3).cwiseProduct(r.row(1)) +
                 inv.row(4).cwiseProduct(r.row(2));
      z.row(1) = inv.row(3).cwiseProduct(r.row(0)) + inv.row(1).cwiseProduct(r.row(1)) +
                 inv.row(5).cwiseProduct(r.row(2));
      z.row(2) = inv.row(4).cwiseProduct(r.row(0)) + inv.row(5).cwiseProduct(r.row(1)) +
                 inv.row(2).cwiseProduct(r.row(2));
    };
    if (m_coarse && m_coarse_stale) {
      m_coarse->build(m, lin_a, lin_d, h, contacts);
      m_coarse_stale = false;
    }
    // a coarse matrix that failed to factorise (not positive definite numerically) is left out
    if (!m_coarse || !m_coarse->ok()) return run(apply, blocks, project);
    // plus the coarse grid's correction P A_c^-1 P^T r (coarse_grid.hpp)
    auto two_level = [&](const Matrix3X& r, Matrix3X& z) {
      blocks(r, z);
      m_coarse->add_correction(r, z);
    };
    return run(apply, two_level, project);
  }
  for (Eigen::Index p = 0; p < m_inv_diag.cols(); ++p)
    m_inv_diag.col(p) = a.diagonal_blocks().middleCols<3>(3 * p).diagonal().cwiseInverse();
  auto jacobi = [&](const Matrix3X& r, Matrix3X& z) { z = r.cwiseProduct(m_inv_diag); };
  return run(apply, jacobi, project);
}

CgResult NewtonLinearSolver::solve_cg(const Model& m, const ImplicitMatrix& a,
                                      const SpringLinearization& lin_k,
                                      const SpringLinearization& lin_a,
                                      const SpringLinearization& lin_d, double h, const Matrix3X& b,
                                      Matrix3X& x, double tolerance, int max_iterations,
                                      const std::vector<ContactConstraint>& contacts,
                                      bool truncate) {
  return with_operators(m, a, lin_k, lin_a, lin_d, h, contacts,
                        [&](auto&& apply, auto&& precondition, auto&& project) {
                          return projected_pcg(apply, precondition, project, b, x, m_cg, tolerance,
                                               max_iterations, truncate);
                        });
}

TrustRegionCgResult NewtonLinearSolver::solve_trust_region(
    const Model& m, const ImplicitMatrix& a, const SpringLinearization& lin_k,
    const SpringLinearization& lin_a, const SpringLinearization& lin_d, double h, const Matrix3X& b,
    const Matrix3X& weights, double radius, Matrix3X& x, double tolerance, int max_iterations,
    const std::vector<ContactConstraint>& contacts) {
  return with_operators(m, a, lin_k, lin_a, lin_d, h, contacts,
                        [&](auto&& apply, auto&& precondition, auto&& project) {
                          return trust_region_pcg(apply, precondition, project, b, weights, radius,
                                                  x, m_cg, tolerance, max_iterations);
                        });
}

}  // namespace cloth
