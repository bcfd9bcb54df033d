#include "cloth/newton_linear_solver.hpp"

namespace cloth {

namespace {

using Interleaved = Eigen::Matrix<double, 3, Eigen::Dynamic>;  // column-major: 3 p + r

}  // namespace

NewtonLinearSolver::NewtonLinearSolver(LinearSolver solver, Eigen::Index dofs) : m_solver(solver) {
  m_inv_diag.setZero(3, dofs / 3);
  m_buf.setZero(3, dofs / 3);
  m_cg.resize(dofs / 3);
  m_b.setZero(dofs);
  m_x.setZero(dofs);
}

CgResult NewtonLinearSolver::solve(const Model& m, const ImplicitMatrix& a,
                                   const SpringLinearization& lin_k,
                                   const SpringLinearization& lin_d, double h, const Matrix3X& b,
                                   Matrix3X& x, double tolerance, int max_iterations,
                                   const std::vector<ContactConstraint>& contacts) {
  if (m_solver != LinearSolver::ldlt)
    return solve_cg(m, a, lin_k, lin_d, h, b, x, tolerance, max_iterations, contacts);
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

CgResult NewtonLinearSolver::solve_cg(const Model& m, const ImplicitMatrix& a,
                                      const SpringLinearization& lin_k,
                                      const SpringLinearization& lin_d, double h, const Matrix3X& b,
                                      Matrix3X& x, double tolerance, int max_iterations,
                                      const std::vector<ContactConstraint>& contacts) {
  // A u = (M + h drag) u - h^2 K u - h D0 u, matrix-free
  auto apply = [&](const Matrix3X& u, Matrix3X& out) {
    for (int r = 0; r < 3; ++r)
      out.row(r) = u.row(r).cwiseProduct(m.mass.transpose()) + (h * m.air_drag) * u.row(r);
    add_newton_product(m.springs, lin_k, lin_d, u, -h * h, -h, out, m_buf);
  };
  // S: the held-axis mask, then I - n n^T at each contact
  auto project = [&](Matrix3X& u) {
    u.array() *= m.free.array();
    remove_normal_parts(contacts, u);
  };
  if (m_solver == LinearSolver::block_jacobi_cg) {
    // z_p = B_p^-1 r_p with B_p particle p's 3 by 3 diagonal block (identity rows when held)
    a.diagonal_block_inverses(m_block_inv);
    auto blocks = [&](const Matrix3X& r, Matrix3X& z) {
      for (Eigen::Index p = 0; p < r.cols(); ++p)
        z.col(p).noalias() = m_block_inv.middleCols<3>(3 * p) * r.col(p);
    };
    return projected_pcg(apply, blocks, project, b, x, m_cg, tolerance, max_iterations);
  }
  for (Eigen::Index p = 0; p < b.cols(); ++p)
    m_inv_diag.col(p) = a.diagonal_blocks().middleCols<3>(3 * p).diagonal().cwiseInverse();
  auto jacobi = [&](const Matrix3X& r, Matrix3X& z) { z = r.cwiseProduct(m_inv_diag); };
  return projected_pcg(apply, jacobi, project, b, x, m_cg, tolerance, max_iterations);
}

}  // namespace cloth
