#include "cloth/implicit_matrix.hpp"

#include <Eigen/LU>
#include <algorithm>

namespace cloth {

namespace {

/// Offset in the value array of entry (row, col); the entry must be in the pattern.
int entry_offset(const Eigen::SparseMatrix<double>& a, int row, int col) {
  const int* begin = a.innerIndexPtr() + a.outerIndexPtr()[col];
  const int* end = a.innerIndexPtr() + a.outerIndexPtr()[col + 1];
  return static_cast<int>(std::lower_bound(begin, end, row) - a.innerIndexPtr());
}

}  // namespace

Matrix3 spring_block(const Model& m, const SpringLinearization& lin_k,
                     const SpringLinearization& lin_d, size_t fi, int p, double h) {
  const auto& L = lin_k.dirs[fi];
  const double k = m.springs.families[fi].stiffness, b = L(3, p);
  const Vector3 d = L.col(p).head<3>(), d0 = lin_d.dirs[fi].col(p).head<3>();
  return h * h * k * ((1.0 - b) * d * d.transpose() + b * Matrix3::Identity()) +
         h * m.springs.damping * d0 * d0.transpose();
}

ImplicitMatrix::ImplicitMatrix(const Model& m, bool whole) {
  if (!whole) return;
  const int n = m.particle_count();
  // the pattern: every particle's diagonal block and both off-diagonal blocks of each spring
  std::vector<Eigen::Triplet<double>> t;
  auto add_block = [&](int p, int q) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) t.emplace_back(3 * p + r, 3 * q + c, 0.0);
  };
  for (int p = 0; p < n; ++p) add_block(p, p);
  for_each_spring(m.springs, [&](int p, int q, size_t) {
    add_block(p, q);
    add_block(q, p);
  });
  m_a.resize(3 * n, 3 * n);
  m_a.setFromTriplets(t.begin(), t.end());
  m_a.makeCompressed();
  // the value offsets of each block's three columns, at its first row
  auto block_slots = [&](int p, int q, std::vector<int>& out) {
    for (int c = 0; c < 3; ++c) out.push_back(entry_offset(m_a, 3 * p, 3 * q + c));
  };
  for (int p = 0; p < n; ++p) block_slots(p, p, m_diag_slots);
  for_each_spring(m.springs, [&](int p, int q, size_t) {
    for (auto [r, c] : {std::pair{p, p}, {q, q}, {p, q}, {q, p}}) block_slots(r, c, m_spring_slots);
  });
  // held axes: identity row and column
  for (int col = 0; col < 3 * n; ++col) {
    for (int k = m_a.outerIndexPtr()[col]; k < m_a.outerIndexPtr()[col + 1]; ++k) {
      const int row = m_a.innerIndexPtr()[k];
      const bool held_row = m.free(row % 3, row / 3) == 0.0;
      const bool held_col = m.free(col % 3, col / 3) == 0.0;
      if (row == col && held_col) m_held_one.push_back(k);
      if (row != col && (held_row || held_col)) m_held_zero.push_back(k);
    }
  }
}

void ImplicitMatrix::assemble(const Model& m, const SpringLinearization& lin_k,
                              const SpringLinearization& lin_d, double h) {
  double* val = m_a.valuePtr();
  std::fill(val, val + m_a.nonZeros(), 0.0);
  // the mass and drag on the diagonal
  for (int p = 0; p < m.particle_count(); ++p)
    for (int c = 0; c < 3; ++c) val[m_diag_slots[3 * p + c] + c] = m.mass[p] + h * m.air_drag;
  // each spring's block B = h^2 J + h c d0 d0^T: +B on both diagonal blocks, -B off them
  int s = 0;
  for_each_spring(m.springs, [&](int p, int, size_t fi) {
    const Matrix3 block = spring_block(m, lin_k, lin_d, fi, p, h);
    const int* slots = &m_spring_slots[12 * s++];
    for (int blk = 0; blk < 4; ++blk) {
      const double sign = blk < 2 ? 1.0 : -1.0;
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) val[slots[3 * blk + c] + r] += sign * block(r, c);
    }
  });
  for (int k : m_held_zero) val[k] = 0.0;
  for (int k : m_held_one) val[k] = 1.0;
  copy_diagonal_blocks();
}

void ImplicitMatrix::copy_diagonal_blocks() {
  const Eigen::Index n = m_a.cols() / 3;
  m_blocks.resize(3, 3 * n);
  const double* val = m_a.valuePtr();
  for (Eigen::Index p = 0; p < n; ++p)
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) m_blocks(r, 3 * p + c) = val[m_diag_slots[3 * p + c] + r];
}

void ImplicitMatrix::assemble_diagonal_blocks(const Model& m, const SpringLinearization& lin_k,
                                              const SpringLinearization& lin_d, double h) {
  const int n = m.particle_count();
  m_blocks.setZero(3, 3 * Eigen::Index(n));
  for (int p = 0; p < n; ++p)
    m_blocks.middleCols<3>(3 * p).diagonal().setConstant(m.mass[p] + h * m.air_drag);
  // each spring's block B = h^2 J + h c d0 d0^T on both ends' diagonal blocks
  for_each_spring(m.springs, [&](int p, int q, size_t fi) {
    const Matrix3 block = spring_block(m, lin_k, lin_d, fi, p, h);
    m_blocks.middleCols<3>(3 * p) += block;
    m_blocks.middleCols<3>(3 * q) += block;
  });
  // held axes: identity row and column, as in assemble()
  for (int p = 0; p < n; ++p)
    for (int r = 0; r < 3; ++r)
      if (m.free(r, p) == 0.0) {
        m_blocks.row(r).segment<3>(3 * p).setZero();
        m_blocks.col(3 * p + r).setZero();
        m_blocks(r, 3 * p + r) = 1.0;
      }
}

void ImplicitMatrix::apply_contacts(const Model& m, const std::vector<ContactConstraint>& contacts,
                                    bool whole) {
  if (contacts.empty()) return;
  for (const ContactConstraint& c : contacts) {
    auto block = m_blocks.middleCols<3>(3 * Eigen::Index(c.particle));
    const Matrix3 s = Matrix3::Identity() - c.normal * c.normal.transpose();
    block = s * block * s + c.normal * c.normal.transpose();
  }
  if (!whole) return;
  // S per particle, the identity unless in contact: kept across calls, set for these contacts
  // and reset at the end
  if (m_filter.empty()) {
    m_filter.assign(static_cast<size_t>(m.particle_count()), Matrix3::Identity());
    m_touching.assign(static_cast<size_t>(m.particle_count()), 0);
  }
  std::vector<Matrix3>& filter = m_filter;
  std::vector<char>& touching = m_touching;
  for (const ContactConstraint& c : contacts) {
    filter[c.particle] -= c.normal * c.normal.transpose();
    touching[c.particle] = 1;
  }
  double* val = m_a.valuePtr();
  auto transform = [&](const int* slots, int p, int q, bool diagonal) {
    Matrix3 b;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) b(r, c) = val[slots[c] + r];
    b = filter[p] * b * filter[q];
    if (diagonal) b += Matrix3::Identity() - filter[p];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) val[slots[c] + r] = b(r, c);
  };
  // the off-diagonal blocks pq and qp of every spring with an end in contact
  int s = 0;
  for_each_spring(m.springs, [&](int p, int q, size_t) {
    const int* slots = &m_spring_slots[12 * s++];
    if (!touching[p] && !touching[q]) return;
    transform(slots + 6, p, q, false);
    transform(slots + 9, q, p, false);
  });
  for (const ContactConstraint& c : contacts) {
    transform(&m_diag_slots[3 * Eigen::Index(c.particle)], c.particle, c.particle, true);
    filter[c.particle].setIdentity();
    touching[c.particle] = 0;
  }
}

void ImplicitMatrix::diagonal_block_inverses(Eigen::Matrix<double, 3, Eigen::Dynamic>& inv) const {
  const Eigen::Index n = m_blocks.cols() / 3;
  inv.resize(3, 3 * n);
  for (Eigen::Index p = 0; p < n; ++p)
    inv.middleCols<3>(3 * p) = m_blocks.middleCols<3>(3 * p).inverse();
}

}  // namespace cloth
