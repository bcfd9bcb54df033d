#pragma once
/// @file newton_linear_solver.hpp
/// Solves implicit Euler's assembled Newton system A dv = b with preconditioned conjugate
/// gradients (Jacobi, 3 by 3 block-Jacobi, or block-Jacobi plus a coarse-grid correction) or a
/// sparse LDL^T whose symbolic factorisation (ordering and elimination tree) is computed once,
/// since A's pattern never changes.

#include <Eigen/SparseCholesky>
#include <memory>

#include "cloth/contact/contact_constraints.hpp"
#include "cloth/solvers/coarse_grid.hpp"
#include "cloth/solvers/conjugate_gradient.hpp"
#include "cloth/solvers/implicit_matrix.hpp"
#include "cloth/solvers/solver_options.hpp"
#include "cloth/solvers/trust_region_cg.hpp"

namespace cloth {

/// One linear solver with its workspace, for one scene.
class NewtonLinearSolver {
 public:
  /// @param solver  cg, block_jacobi_cg, two_level_cg or ldlt (not automatic)
  NewtonLinearSolver(const Model& m, LinearSolver solver);

  /// A new step begins: two_level_cg rebuilds its coarse matrix at the next solve and keeps
  /// it for the rest of the step (a preconditioner need not follow every Newton iterate).
  void start_step() { m_coarse_stale = true; }

  /// Solves A x = b for A = M + h drag - h D - h^2 K with K from lin_k and D's directions from
  /// lin_d. CG applies A matrix-free (the spring kernels are several times cheaper than a sparse
  /// product); a, assembled from lin_a (the same as lin_k, or its clamped form when lin_k may be
  /// indefinite), gives the preconditioner or, for ldlt, the factorisation (lin_k unused).
  /// With contacts, A and b are filtered by I - n n^T at each contact particle (for ldlt, a
  /// must already be: ImplicitMatrix::apply_contacts).
  /// @param b         3 by #P right-hand side, zero on held axes and contact normals
  /// @param x         3 by #P solution, zero on held axes and contact normals, written
  /// @param truncate  CG stops at negative curvature (conjugate_gradient.hpp)
  /// @return CG iterations and relative residual (0 and 0 for ldlt)
  CgResult solve(const Model& m, const ImplicitMatrix& a, const SpringLinearization& lin_k,
                 const SpringLinearization& lin_a, const SpringLinearization& lin_d, double h,
                 const Matrix3X& b, Matrix3X& x, double tolerance, int max_iterations,
                 const std::vector<ContactConstraint>& contacts, bool truncate = false);

  /// The trust-region subproblem of the same system: min -b.x + 1/2 x.A x over
  /// |x|_W <= radius by Steihaug-Toint CG (trust_region_cg.hpp), A from lin_k (may be
  /// indefinite), the preconditioner from a (assembled from lin_a, positive definite). CG
  /// solvers only (not ldlt).
  /// @param weights  3 by #P weights of the region's norm
  /// @param radius   the region's radius in that norm
  TrustRegionCgResult solve_trust_region(const Model& m, const ImplicitMatrix& a,
                                         const SpringLinearization& lin_k,
                                         const SpringLinearization& lin_a,
                                         const SpringLinearization& lin_d, double h,
                                         const Matrix3X& b, const Matrix3X& weights, double radius,
                                         Matrix3X& x, double tolerance, int max_iterations,
                                         const std::vector<ContactConstraint>& contacts);

  /// False when the last ldlt factorisation failed (A not positive definite numerically).
  bool ok() const { return m_ok; }

 private:
  CgResult solve_cg(const Model& m, const ImplicitMatrix& a, const SpringLinearization& lin_k,
                    const SpringLinearization& lin_a, const SpringLinearization& lin_d, double h,
                    const Matrix3X& b, Matrix3X& x, double tolerance, int max_iterations,
                    const std::vector<ContactConstraint>& contacts, bool truncate);
  /// Calls run(apply, precondition, project) with the system's product, this solver's
  /// preconditioner and the filter S, and returns what it returns.
  template <class Run>
  auto with_operators(const Model& m, const ImplicitMatrix& a, const SpringLinearization& lin_k,
                      const SpringLinearization& lin_a, const SpringLinearization& lin_d, double h,
                      const std::vector<ContactConstraint>& contacts, Run&& run);

  LinearSolver m_solver;
  bool m_analyzed = false;
  bool m_ok = true;
  bool m_coarse_stale = true;
  std::unique_ptr<CoarseGrid> m_coarse;  // two_level_cg
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> m_ldlt;
  ImplicitMatrix::SymmetricRows m_block_inv;  // 6 by #P: xx, yy, zz, xy, xz, yz
  Matrix3X m_inv_diag, m_buf;
  CgWorkspace m_cg;
  Eigen::VectorXd m_b, m_x;  // interleaved 3 #P, for ldlt
};

}  // namespace cloth
