#pragma once
/// @file implicit_matrix.hpp
/// The Newton matrix of implicit Euler, A = M + h drag I - h D - h^2 K (K with the hinge
/// bending's constant -Q on every axis, bending_form.hpp), assembled into a
/// sparsity pattern fixed per scene so that a direct solver reuses its symbolic factorisation.
///
/// Unknowns are interleaved, 3 p + r for axis r of particle p. K = df/dx comes from the
/// linearisation at the Newton iterate, D = df/dv from the one at the step's start. A held axis
/// has its row and column replaced by the identity, so its increment is exactly zero.

#include <Eigen/SparseCore>
#include <vector>

#include "cloth/contact/contact_constraints.hpp"
#include "cloth/forces/spring_jacobians.hpp"
#include "cloth/model/model.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// The block B = h^2 J + h c d0 d0^T of the spring in slot s of group g (spring_set.hpp), J
/// from lin_k and the damper's direction d0 from lin_d: A holds +B on both ends' diagonal blocks
/// and -B off them.
Matrix3 spring_block(const Model& m, const SpringLinearization& lin_k,
                     const SpringLinearization& lin_d, size_t g, int s, double h);

/// A in compressed column storage, with the value offsets of every spring's blocks.
class ImplicitMatrix {
 public:
  /// Builds the pattern of m's springs (3 #P by 3 #P).
  /// @param whole  false: only the diagonal blocks will be assembled (assemble_diagonal_blocks;
  ///               assemble() and apply_contacts(whole) are then not to be called)
  explicit ImplicitMatrix(const Model& m, bool whole = true);

  /// Fills A's values for step h.
  /// @param lin_k  linearisation giving K (the Newton iterate)
  /// @param lin_d  linearisation giving D's directions (the step's start)
  void assemble(const Model& m, const SpringLinearization& lin_k, const SpringLinearization& lin_d,
                double h);

  /// Fills only A's 3 by 3 diagonal blocks for step h, all a preconditioner needs (the
  /// conjugate gradients apply A matrix-free): the same values as assemble() there.
  void assemble_diagonal_blocks(const Model& m, const SpringLinearization& lin_k,
                                const SpringLinearization& lin_d, double h);

  /// Filters A by S = I - n n^T at each contact particle: S A S + n n^T on its diagonal
  /// block, so that the normal part of the solution is zero and A stays positive definite.
  /// @param whole  also the assembled matrix (after assemble()), not only the diagonal blocks
  void apply_contacts(const Model& m, const std::vector<ContactConstraint>& contacts, bool whole);

  /// Adds a symmetric 3 by 3 block to A's diagonal block of each of the given particles (each
  /// free on every axis): the barrier contacts' h^2 kappa b'' n n^T (contact_barrier.hpp).
  /// Kept until the next call, so that the conjugate gradients' products add them too
  /// (particle_blocks()). Call after an assembly; an empty list clears them.
  /// @param whole  also the assembled matrix (after assemble()), not only the diagonal blocks
  void add_particle_blocks(const std::vector<int>& particles, const std::vector<Matrix3>& blocks,
                           bool whole);

  /// The particles and blocks of the last add_particle_blocks().
  const std::vector<int>& block_particles() const { return m_extra_particles; }
  const std::vector<Matrix3>& particle_blocks() const { return m_extra_blocks; }

  /// out += the particle blocks times u (3 by #P each).
  void add_particle_block_product(const Matrix3X& u, Matrix3X& out) const;

  /// 3 #P by 3 #P, symmetric, both triangles stored; filled by assemble().
  const Eigen::SparseMatrix<double>& matrix() const { return m_a; }

  /// A's diagonal blocks, block p in columns 3 p .. 3 p + 2; filled by either assembly.
  const Eigen::Matrix<double, 3, Eigen::Dynamic>& diagonal_blocks() const { return m_blocks; }

  /// Symmetric 3 by 3 blocks as six rows over the particles: xx, yy, zz, xy, xz, yz.
  using SymmetricRows = Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor>;

  /// Inverses of the 3 by 3 diagonal blocks (symmetric, like the blocks).
  /// @param inv  6 by #P, written
  void diagonal_block_inverses(SymmetricRows& inv) const;

 private:
  using LinearizedFamily = Eigen::Matrix<double, 4, Eigen::Dynamic, Eigen::RowMajor>;

  /// Copies A's diagonal blocks out of m_a into m_blocks.
  void copy_diagonal_blocks();
  /// Adds family fi's spring blocks to m_sym at both ends of each spring.
  void add_family_diagonal(const Model& m, const LinearizedFamily& lk, const LinearizedFamily& ld,
                           size_t fi, double h);
  /// Adds the general list's spring blocks to m_sym at both ends of each spring.
  void add_list_diagonal(const Model& m, const LinearizedFamily& lk, const LinearizedFamily& ld,
                         double h);

  Eigen::SparseMatrix<double> m_a;
  Eigen::Matrix<double, 3, Eigen::Dynamic> m_blocks;
  SymmetricRows m_sym;              // assemble_diagonal_blocks: per particle xx, yy, zz, xy, xz, yz
  SymmetricRows m_family_sym;       // the same per spring of one family
  std::vector<Matrix3> m_filter;    // apply_contacts(whole): per particle I - n n^T, or I
  std::vector<char> m_touching;     // apply_contacts(whole): per particle, 1 if in contact
  std::vector<int> m_spring_slots;  // per spring 4 blocks (pp, qq, pq, qp) by 3 columns
  std::vector<int> m_bending_slots;     // per entry of the hinge bending's Q, its block's 3 columns
  std::vector<int> m_diag_slots;        // per particle and column, the offset of row 3 p
  std::vector<int> m_held_zero;         // off-diagonal entries in a held row or column
  std::vector<int> m_held_one;          // diagonal entries of held axes
  std::vector<int> m_extra_particles;   // add_particle_blocks: the particles
  std::vector<Matrix3> m_extra_blocks;  // and their blocks
};

}  // namespace cloth
