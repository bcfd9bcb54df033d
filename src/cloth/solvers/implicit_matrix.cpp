#include "cloth/solvers/implicit_matrix.hpp"

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

/// Calls visit(p, q, Q(p, q)) for every stored entry of the hinge bending's form, column by
/// column.
template <class Visit>
void for_each_bending_entry(const Model& m, Visit&& visit) {
  const Eigen::SparseMatrix<double>& q = m.springs.bending.q;
  for (int col = 0; col < q.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(q, col); it; ++it)
      visit(int(it.row()), col, it.value());
}

}  // namespace

Matrix3 spring_block(const Model& m, const SpringLinearization& lin_k,
                     const SpringLinearization& lin_d, size_t g, int s, double h) {
  const auto& L = lin_k.dirs[g];
  const double k = m.springs.stiffness(g, s), b = L(3, s);
  const Vector3 d = L.col(s).head<3>(), d0 = lin_d.dirs[g].col(s).head<3>();
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
  for_each_spring(m.springs, [&](int p, int q, size_t, int) {
    add_block(p, q);
    add_block(q, p);
  });
  for_each_bending_entry(m, [&](int p, int q, double) { add_block(p, q); });
  m_a.resize(3 * n, 3 * n);
  m_a.setFromTriplets(t.begin(), t.end());
  m_a.makeCompressed();
  // the value offsets of each block's three columns, at its first row
  auto block_slots = [&](int p, int q, std::vector<int>& out) {
    for (int c = 0; c < 3; ++c) out.push_back(entry_offset(m_a, 3 * p, 3 * q + c));
  };
  for (int p = 0; p < n; ++p) block_slots(p, p, m_diag_slots);
  for_each_spring(m.springs, [&](int p, int q, size_t, int) {
    for (auto [r, c] : {std::pair{p, p}, {q, q}, {p, q}, {q, p}}) block_slots(r, c, m_spring_slots);
  });
  for_each_bending_entry(m, [&](int p, int q, double) { block_slots(p, q, m_bending_slots); });
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
  for_each_spring(m.springs, [&](int, int, size_t g, int slot) {
    const Matrix3 block = spring_block(m, lin_k, lin_d, g, slot, h);
    const int* slots = &m_spring_slots[12 * s++];
    for (int blk = 0; blk < 4; ++blk) {
      const double sign = blk < 2 ? 1.0 : -1.0;
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) val[slots[3 * blk + c] + r] += sign * block(r, c);
    }
  });
  // the hinge bending's h^2 Q on every axis: its stiffness is -Q
  int e = 0;
  for_each_bending_entry(m, [&](int, int, double q) {
    const int* slots = &m_bending_slots[3 * e++];
    for (int c = 0; c < 3; ++c) val[slots[c] + c] += h * h * q;
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
  // the six entries xx, yy, zz, xy, xz, yz of each particle's symmetric block, one row each
  m_sym.setZero(6, n);
  for (size_t fi = 0; fi < m.springs.families.size(); ++fi)
    add_family_diagonal(m, lin_k.dirs[fi], lin_d.dirs[fi], fi, h);
  if (!m.springs.list.empty()) add_list_diagonal(m, lin_k.dirs.back(), lin_d.dirs.back(), h);
  if (!m.springs.bending.empty()) {
    const VectorX q = m.springs.bending.q.diagonal();
    for (int r = 0; r < 3; ++r) m_sym.row(r) += (h * h) * q.transpose();
  }
  m_blocks.resize(3, 3 * Eigen::Index(n));
  const double diagonal_extra = h * m.air_drag;
  for (int p = 0; p < n; ++p) {
    auto block = m_blocks.middleCols<3>(3 * Eigen::Index(p));
    const double md = m.mass[p] + diagonal_extra;
    block << m_sym(0, p) + md, m_sym(3, p), m_sym(4, p),  //
        m_sym(3, p), m_sym(1, p) + md, m_sym(5, p),       //
        m_sym(4, p), m_sym(5, p), m_sym(2, p) + md;
  }
  // held axes: identity row and column, as in assemble()
  for (int p = 0; p < n; ++p)
    for (int r = 0; r < 3; ++r)
      if (m.free(r, p) == 0.0) {
        m_blocks.row(r).segment<3>(3 * p).setZero();
        m_blocks.col(3 * p + r).setZero();
        m_blocks(r, 3 * p + r) = 1.0;
      }
}

void ImplicitMatrix::add_family_diagonal(const Model& m, const LinearizedFamily& lk,
                                         const LinearizedFamily& ld, size_t fi, double h) {
  // each spring's block B = h^2 k ((1 - b) d d^T + b I) + h c d0 d0^T (spring_block), computed
  // for every slot (an empty slot has d = d0 = 0 and b = 0, so B = 0), then added to both ends
  const SpringFamily& fam = m.springs.families[fi];
  const int o = fam.offset, slots = fam.slots();
  const double hk = h * h * fam.stiffness, hc = h * m.springs.damping;
  m_family_sym.resize(6, slots);
  const double *dx = lk.row(0).data(), *dy = lk.row(1).data(), *dz = lk.row(2).data();
  const double* b = lk.row(3).data();
  const double *ex = ld.row(0).data(), *ey = ld.row(1).data(), *ez = ld.row(2).data();
  double* __restrict out[6];
  for (int e = 0; e < 6; ++e) out[e] = m_family_sym.row(e).data();
  for (int p = 0; p < slots; ++p) {
    const double t = hk * (1.0 - b[p]), s = hk * b[p];
    out[0][p] = t * dx[p] * dx[p] + s + hc * ex[p] * ex[p];
    out[1][p] = t * dy[p] * dy[p] + s + hc * ey[p] * ey[p];
    out[2][p] = t * dz[p] * dz[p] + s + hc * ez[p] * ez[p];
    out[3][p] = t * dx[p] * dy[p] + hc * ex[p] * ey[p];
    out[4][p] = t * dx[p] * dz[p] + hc * ex[p] * ez[p];
    out[5][p] = t * dy[p] * dz[p] + hc * ey[p] * ez[p];
  }
  for (int e = 0; e < 6; ++e) {
    m_sym.row(e).head(slots) += m_family_sym.row(e);
    m_sym.row(e).segment(o, slots) += m_family_sym.row(e);
  }
}

void ImplicitMatrix::add_list_diagonal(const Model& m, const LinearizedFamily& lk,
                                       const LinearizedFamily& ld, double h) {
  // the general list's blocks B, as in add_family_diagonal, added to both ends one by one
  const SpringList& l = m.springs.list;
  const double hc = h * m.springs.damping;
  for (int i = 0; i < l.size(); ++i) {
    const double hk = h * h * l.stiffness[size_t(i)];
    const double t = hk * (1.0 - lk(3, i)), s = hk * lk(3, i);
    const double dx = lk(0, i), dy = lk(1, i), dz = lk(2, i);
    const double ex = ld(0, i), ey = ld(1, i), ez = ld(2, i);
    const double e[6] = {t * dx * dx + s + hc * ex * ex, t * dy * dy + s + hc * ey * ey,
                         t * dz * dz + s + hc * ez * ez, t * dx * dy + hc * ex * ey,
                         t * dx * dz + hc * ex * ez,     t * dy * dz + hc * ey * ez};
    for (int r = 0; r < 6; ++r) {
      m_sym(r, l.a[size_t(i)]) += e[r];
      m_sym(r, l.b[size_t(i)]) += e[r];
    }
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
  for_each_spring(m.springs, [&](int p, int q, size_t, int) {
    const int* slots = &m_spring_slots[12 * s++];
    if (!touching[p] && !touching[q]) return;
    transform(slots + 6, p, q, false);
    transform(slots + 9, q, p, false);
  });
  int e = 0;
  for_each_bending_entry(m, [&](int p, int q, double) {
    const int* slots = &m_bending_slots[3 * e++];
    if (p != q && (touching[p] || touching[q])) transform(slots, p, q, false);
  });
  for (const ContactConstraint& c : contacts) {
    transform(&m_diag_slots[3 * Eigen::Index(c.particle)], c.particle, c.particle, true);
    filter[c.particle].setIdentity();
    touching[c.particle] = 0;
  }
}

void ImplicitMatrix::diagonal_block_inverses(SymmetricRows& inv) const {
  const Eigen::Index n = m_blocks.cols() / 3;
  inv.resize(6, n);
  for (Eigen::Index p = 0; p < n; ++p) {
    const Matrix3 b = m_blocks.middleCols<3>(3 * p).inverse();
    inv.col(p) << b(0, 0), b(1, 1), b(2, 2), b(0, 1), b(0, 2), b(1, 2);
  }
}

void ImplicitMatrix::add_particle_blocks(const std::vector<int>& particles,
                                         const std::vector<Matrix3>& blocks, bool whole) {
  m_extra_particles = particles;
  m_extra_blocks = blocks;
  double* val = whole ? m_a.valuePtr() : nullptr;
  for (size_t k = 0; k < particles.size(); ++k) {
    const Eigen::Index p = particles[k];
    m_blocks.middleCols<3>(3 * p) += blocks[k];
    if (!val) continue;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) val[m_diag_slots[3 * p + c] + r] += blocks[k](r, c);
  }
}

void ImplicitMatrix::add_particle_block_product(const Matrix3X& u, Matrix3X& out) const {
  for (size_t k = 0; k < m_extra_particles.size(); ++k) {
    const Eigen::Index p = m_extra_particles[k];
    out.col(p) += m_extra_blocks[k] * u.col(p);
  }
}

}  // namespace cloth
