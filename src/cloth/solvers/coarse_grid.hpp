#pragma once
/// @file coarse_grid.hpp
/// The coarse level of the two-level preconditioner (linear_solver = "two-level-cg"): a grid
/// of about one particle in `coarsening` along u and along v, bilinear interpolation P from it
/// to the cloth, and the Galerkin matrix A_c = P^T A P of implicit Euler's filtered Newton
/// matrix A (held axes and contacts as in implicit_matrix.hpp), factorised with a sparse
/// LDL^T. The preconditioner is z = B^-1 r + P A_c^-1 P^T r with B A's 3 by 3 diagonal blocks:
/// the blocks damp what varies from particle to particle, the coarse solve what is smooth over
/// the cloth, which block-Jacobi alone reaches only in about one CG iteration per particle
/// along the cloth.
///
/// P interpolates each axis independently, so A_c holds the cloth's stretch as it is folded
/// now, not an isotropic rest-shape Laplacian.

#include <Eigen/SparseCholesky>
#include <array>
#include <vector>

#include "cloth/contact/contact_constraints.hpp"
#include "cloth/forces/spring_jacobians.hpp"
#include "cloth/model/model.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// One coarse grid for one scene, with its factorised Galerkin matrix.
class CoarseGrid {
 public:
  /// Linear interpolation along one axis of n fine nodes from c coarse nodes spread evenly
  /// over it: fine node i's left parent and that parent's weight (the right one gets the rest;
  /// with c = 1 the one node gets all).
  struct AxisWeights {
    std::vector<int> left;
    std::vector<double> weight;
    std::vector<int> first;  // c + 1 entries: fine nodes first[k] .. first[k + 1] have left k
  };

  /// @param coarsening  fine particles per coarse interval, at most, along each grid axis (>= 2)
  /// @throws std::invalid_argument if m's springs have a general list (not a grid's families),
  ///         naming the linear solver to use instead
  CoarseGrid(const Model& m, int coarsening);

  /// Forms A_c = P^T A P for A at lin_k, lin_d and step h, filtered by m's held axes and
  /// these contacts, and factorises it.
  void build(const Model& m, const SpringLinearization& lin_k, const SpringLinearization& lin_d,
             double h, const std::vector<ContactConstraint>& contacts);

  /// z += P A_c^-1 P^T r (both 3 by #P).
  void add_correction(const Matrix3X& r, Matrix3X& z);

  /// A_c as last built (3 #C by 3 #C, both triangles, unknowns 3 c + r).
  const Eigen::SparseMatrix<double>& matrix() const { return m_ac; }
  /// P (3 #P by 3 #C), for tests.
  Eigen::SparseMatrix<double> prolongation() const;
  /// Number of coarse nodes, #C.
  int nodes() const { return m_cu * m_cv; }
  /// False when the last factorisation failed.
  bool ok() const { return m_ok; }

 private:
  /// A particle's (up to) four coarse parents and their weights (0 where absent).
  struct Parents {
    std::array<int, 4> node{};
    std::array<double, 4> weight{};
  };
  /// The slot of block (a, b) in m_blocks; b must be within the stencil of a.
  int slot(int a, int b) const;
  /// Adds P^T (S (M + h drag) S + I - S) P, with S the filters of the last build().
  void add_diagonal(const Model& m, double h);
  /// Adds each spring's G^T B G, G = S_p P_p - S_q P_q (A holds +-B between p and q).
  void add_springs(const Model& m, const SpringLinearization& lin_k,
                   const SpringLinearization& lin_d, double h);
  void build_pattern();
  /// m_rc = P^T r.
  void restrict_to_coarse(const Matrix3X& r);
  /// z += P m_xc.
  void add_prolonged(Matrix3X& z);

  int m_cu = 1, m_cv = 1;  // coarse nodes along u and v
  int m_ru = 0, m_rv = 0;  // stencil half-widths along u and v, in coarse nodes
  AxisWeights m_u, m_v;
  std::vector<double> m_half;  // add_correction's scratch, 3 by nv by cu
  std::vector<Parents> m_parents;
  std::vector<Matrix3> m_blocks;    // per coarse node a, its stencil's blocks (a, b): only those
                                    // with a <= b are filled, the others are their transposes
  std::vector<int> m_value_source;  // per nonzero of m_ac: 9 * slot + 3 * col + row in m_blocks
  Eigen::SparseMatrix<double> m_ac;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> m_ldlt;
  Eigen::VectorXd m_rc, m_xc;     // coarse right-hand side and solution, 3 #C interleaved
  std::vector<Matrix3> m_filter;  // per particle: S, the held-axis mask, or I - n n^T during
                                  // build() at a contact
  std::vector<char> m_filtered;   // per particle: S != I
  bool m_ok = true;
};

}  // namespace cloth
