#include "cloth/solvers/coarse_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "cloth/model/spring_set.hpp"
#include "cloth/solvers/implicit_matrix.hpp"

namespace cloth {

namespace {

CoarseGrid::AxisWeights axis_weights(int n, int c) {
  CoarseGrid::AxisWeights w;
  w.left.resize(static_cast<size_t>(n));
  w.weight.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    if (c == 1) {
      w.left[i] = 0;
      w.weight[i] = 1.0;
      continue;
    }
    const double t = double(i) * (c - 1) / (n - 1);
    const int k = std::min(static_cast<int>(t), c - 2);
    w.left[i] = k;
    w.weight[i] = 1.0 - (t - k);
  }
  // left parents do not decrease along the axis: each node's run of fine nodes
  w.first.assign(static_cast<size_t>(c) + 1, n);
  for (int i = n - 1; i >= 0; --i) w.first[w.left[i]] = i;
  for (int k = c - 1; k >= 0; --k) w.first[k] = std::min(w.first[k], w.first[k + 1]);
  return w;
}

/// Coarse nodes along an axis of n particles: intervals of at most `coarsening` particles.
int coarse_count(int n, int coarsening) {
  return n <= 1 ? 1 : (n - 1 + coarsening - 1) / coarsening + 1;
}

/// m itself if its springs are a grid's families; otherwise throws std::invalid_argument: the
/// coarse grid interpolates along the grid's rows and columns, which a general list has not.
const Model& grid_only(const Model& m) {
  if (!m.springs.list.empty())
    throw std::invalid_argument(
        "linear_solver = \"two-level-cg\" needs a rectangular grid cloth (its coarse grid "
        "follows the grid's rows and columns); for a cloth of general springs (a mesh) use "
        "linear_solver = \"block-jacobi-cg\" (or \"auto\", which chooses it)");
  return m;
}

/// Up to eight (coarse node, coefficient) terms of P_p - P_q, equal nodes merged.
struct Difference {
  int count = 0;
  std::array<int, 8> node{};
  std::array<double, 8> coef{};
  void add(int n, double c) {
    if (c == 0.0) return;
    for (int k = 0; k < count; ++k)
      if (node[k] == n) {
        coef[k] += c;
        return;
      }
    node[count] = n;
    coef[count++] = c;
  }
};

}  // namespace

CoarseGrid::CoarseGrid(const Model& m, int coarsening)
    : m_cu(coarse_count(grid_only(m).nu, coarsening)),
      m_cv(coarse_count(m.nv, coarsening)),
      m_u(axis_weights(m.nu, m_cu)),
      m_v(axis_weights(m.nv, m_cv)) {
  const AxisWeights& wu = m_u;
  const AxisWeights& wv = m_v;
  m_parents.resize(static_cast<size_t>(m.particle_count()));
  for (int j = 0; j < m.nv; ++j)
    for (int i = 0; i < m.nu; ++i) {
      Parents& par = m_parents[static_cast<size_t>(j * m.nu + i)];
      const int ku = wu.left[i], kv = wv.left[j];
      const double u0 = wu.weight[i], v0 = wv.weight[j];
      // a parent past the grid's edge has weight 0; it is clamped to a real node
      const int ku1 = std::min(ku + 1, m_cu - 1), kv1 = std::min(kv + 1, m_cv - 1);
      par.node = {kv * m_cu + ku, kv * m_cu + ku1, kv1 * m_cu + ku, kv1 * m_cu + ku1};
      par.weight = {u0 * v0, (1 - u0) * v0, u0 * (1 - v0), (1 - u0) * (1 - v0)};
    }
  // the stencil: how far apart, in coarse nodes, two parents of a spring's ends can be
  for_each_spring(m.springs, [&](int p, int q, size_t, int) {
    for (int a : m_parents[p].node)
      for (int b : m_parents[q].node) {
        m_ru = std::max(m_ru, std::abs(a % m_cu - b % m_cu));
        m_rv = std::max(m_rv, std::abs(a / m_cu - b / m_cu));
      }
  });
  // and any two parents of one particle
  m_ru = std::max(m_ru, m_cu > 1 ? 1 : 0);
  m_rv = std::max(m_rv, m_cv > 1 ? 1 : 0);
  m_blocks.assign(static_cast<size_t>(nodes()) * (2 * m_ru + 1) * (2 * m_rv + 1), Matrix3::Zero());
  // S per particle: the held-axis mask, fixed per scene; build() sets contacts' and resets them
  m_filter.resize(m_parents.size());
  m_filtered.resize(m_parents.size());
  for (int p = 0; p < m.particle_count(); ++p) {
    m_filter[p] = m.free.col(p).asDiagonal();
    m_filtered[p] = m.free.col(p).minCoeff() == 0.0;
  }
  m_rc.setZero(3 * nodes());
  m_xc.setZero(3 * nodes());
  build_pattern();
}

int CoarseGrid::slot(int a, int b) const {
  const int du = b % m_cu - a % m_cu + m_ru, dv = b / m_cu - a / m_cu + m_rv;
  return (a * (2 * m_rv + 1) + dv) * (2 * m_ru + 1) + du;
}

void CoarseGrid::build_pattern() {
  // every pair of nodes within the stencil, 3 by 3 each; unknowns 3 c + r
  std::vector<Eigen::Triplet<double>> t;
  for (int a = 0; a < nodes(); ++a)
    for (int bv = std::max(0, a / m_cu - m_rv); bv <= std::min(m_cv - 1, a / m_cu + m_rv); ++bv)
      for (int bu = std::max(0, a % m_cu - m_ru); bu <= std::min(m_cu - 1, a % m_cu + m_ru); ++bu) {
        const int b = bv * m_cu + bu;
        // only blocks (a, b) with a <= b are accumulated; the others are their transposes
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r)
            t.emplace_back(3 * a + r, 3 * b + c,
                           a <= b ? 9.0 * slot(a, b) + 3 * c + r : 9.0 * slot(b, a) + 3 * r + c);
      }
  m_ac.resize(3 * nodes(), 3 * nodes());
  m_ac.setFromTriplets(t.begin(), t.end());
  m_ac.makeCompressed();
  // the values were the sources' indices; keep them and analyse the pattern once
  m_value_source.resize(static_cast<size_t>(m_ac.nonZeros()));
  for (Eigen::Index k = 0; k < m_ac.nonZeros(); ++k)
    m_value_source[k] = static_cast<int>(std::lround(m_ac.valuePtr()[k]));
  m_ldlt.analyzePattern(m_ac);
}

void CoarseGrid::build(const Model& m, const SpringLinearization& lin_k,
                       const SpringLinearization& lin_d, double h,
                       const std::vector<ContactConstraint>& contacts) {
  // S is I - n n^T at a contact (contacts are on all-free particles, whose S is otherwise I)
  for (const ContactConstraint& c : contacts) {
    m_filter[c.particle] = Matrix3::Identity() - c.normal * c.normal.transpose();
    m_filtered[c.particle] = 1;
  }
  std::fill(m_blocks.begin(), m_blocks.end(), Matrix3::Zero());
  add_diagonal(m, h);
  add_springs(m, lin_k, lin_d, h);
  double* val = m_ac.valuePtr();
  for (size_t k = 0; k < m_value_source.size(); ++k) {
    const int s = m_value_source[k];
    val[k] = m_blocks[s / 9](s % 3, (s % 9) / 3);
  }
  m_ldlt.factorize(m_ac);
  m_ok = m_ldlt.info() == Eigen::Success;
  for (const ContactConstraint& c : contacts) {
    m_filter[c.particle].setIdentity();
    m_filtered[c.particle] = 0;
  }
}

void CoarseGrid::add_diagonal(const Model& m, double h) {
  // P^T (S (M + h drag) S + I - S) P: the identity where S takes an axis or a normal out
  for (int p = 0; p < m.particle_count(); ++p) {
    const Parents& par = m_parents[p];
    const double mp = m.mass[p] + h * m.air_drag;
    const Matrix3 d = m_filtered[p] ? Matrix3(mp * m_filter[p] + Matrix3::Identity() - m_filter[p])
                                    : Matrix3(mp * Matrix3::Identity());
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        const double w = par.weight[i] * par.weight[j];
        if (w != 0.0 && par.node[i] <= par.node[j])
          m_blocks[slot(par.node[i], par.node[j])] += w * d;
      }
  }
}

void CoarseGrid::add_springs(const Model& m, const SpringLinearization& lin_k,
                             const SpringLinearization& lin_d, double h) {
  // a spring adds G^T B G with G = S_p P_p - S_q P_q (its rows of A are +-B between p and q)
  for_each_spring(m.springs, [&](int p, int q, size_t group, int s) {
    const Matrix3 b = spring_block(m, lin_k, lin_d, group, s, h);
    Difference diff;
    for (int i = 0; i < 4; ++i) diff.add(m_parents[p].node[i], m_parents[p].weight[i]);
    for (int i = 0; i < 4; ++i) diff.add(m_parents[q].node[i], -m_parents[q].weight[i]);
    // the upper blocks only (a node appears once in diff, and b is symmetric)
    auto upper = [&](int i, int j) {
      return slot(std::min(diff.node[i], diff.node[j]), std::max(diff.node[i], diff.node[j]));
    };
    if (!m_filtered[p] && !m_filtered[q]) {
      for (int i = 0; i < diff.count; ++i)
        for (int j = i; j < diff.count; ++j)
          m_blocks[upper(i, j)] += (diff.coef[i] * diff.coef[j]) * b;
      return;
    }
    // a filtered end: G's block at coarse node c is w_pc S_p - w_qc S_q
    std::array<Matrix3, 8> g;
    for (int i = 0; i < diff.count; ++i) {
      g[i].setZero();
      for (int k = 0; k < 4; ++k) {
        if (m_parents[p].node[k] == diff.node[i]) g[i] += m_parents[p].weight[k] * m_filter[p];
        if (m_parents[q].node[k] == diff.node[i]) g[i] -= m_parents[q].weight[k] * m_filter[q];
      }
    }
    for (int i = 0; i < diff.count; ++i)
      for (int j = i; j < diff.count; ++j) {
        const Matrix3 block = g[i].transpose() * b * g[j];
        m_blocks[upper(i, j)] += diff.node[i] < diff.node[j] ? block : Matrix3(block.transpose());
      }
  });
}

void CoarseGrid::add_correction(const Matrix3X& r, Matrix3X& z) {
  restrict_to_coarse(r);
  m_xc = m_ldlt.solve(m_rc);
  add_prolonged(z);
}

void CoarseGrid::restrict_to_coarse(const Matrix3X& r) {
  // P is bilinear, so P^T goes one grid axis at a time, through m_half (cu by nv per axis); the
  // particles whose left parent along u is k are the contiguous run first[k] .. first[k + 1]
  const int nu = static_cast<int>(m_u.left.size()), nv = static_cast<int>(m_v.left.size());
  m_half.assign(static_cast<size_t>(3) * nv * m_cu, 0.0);
  for (int axis = 0; axis < 3; ++axis)
    for (int j = 0; j < nv; ++j) {
      const double* __restrict rj = r.row(axis).data() + Eigen::Index(j) * nu;
      double* hj = &m_half[(static_cast<size_t>(axis) * nv + j) * m_cu];
      const double* __restrict w = m_u.weight.data();
      for (int k = 0; k < m_cu; ++k) {
        double to_left = 0.0, to_right = 0.0;
#pragma omp simd reduction(+ : to_left, to_right)
        for (int i = m_u.first[k]; i < m_u.first[k + 1]; ++i) {
          to_left += w[i] * rj[i];
          to_right += (1.0 - w[i]) * rj[i];
        }
        hj[k] += to_left;
        if (k + 1 < m_cu) hj[k + 1] += to_right;
      }
    }
  m_rc.setZero();
  for (int axis = 0; axis < 3; ++axis)
    for (int j = 0; j < nv; ++j) {
      const double* hj = &m_half[(static_cast<size_t>(axis) * nv + j) * m_cu];
      const int l = m_v.left[j];
      const double w = m_v.weight[j];
      for (int k = 0; k < m_cu; ++k) {
        m_rc[3 * (l * m_cu + k) + axis] += w * hj[k];
        if (m_cv > 1) m_rc[3 * ((l + 1) * m_cu + k) + axis] += (1.0 - w) * hj[k];
      }
    }
}

void CoarseGrid::add_prolonged(Matrix3X& z) {
  // z += P x_c: along v into m_half, then along u onto each particle run
  const int nu = static_cast<int>(m_u.left.size()), nv = static_cast<int>(m_v.left.size());
  for (int axis = 0; axis < 3; ++axis)
    for (int j = 0; j < nv; ++j) {
      double* hj = &m_half[(static_cast<size_t>(axis) * nv + j) * m_cu];
      const int l = m_v.left[j], l1 = std::min(l + 1, m_cv - 1);
      const double w = m_v.weight[j];
      for (int k = 0; k < m_cu; ++k)
        hj[k] = w * m_xc[3 * (l * m_cu + k) + axis] + (1.0 - w) * m_xc[3 * (l1 * m_cu + k) + axis];
      double* __restrict zj = z.row(axis).data() + Eigen::Index(j) * nu;
      const double* __restrict wu = m_u.weight.data();
      for (int k = 0; k < m_cu; ++k) {
        const double left = hj[k], right = hj[std::min(k + 1, m_cu - 1)];
        for (int i = m_u.first[k]; i < m_u.first[k + 1]; ++i)
          zj[i] += wu[i] * left + (1.0 - wu[i]) * right;
      }
    }
}

Eigen::SparseMatrix<double> CoarseGrid::prolongation() const {
  std::vector<Eigen::Triplet<double>> t;
  for (size_t p = 0; p < m_parents.size(); ++p)
    for (int i = 0; i < 4; ++i)
      for (int r = 0; r < 3; ++r)
        if (m_parents[p].weight[i] != 0.0)
          t.emplace_back(3 * int(p) + r, 3 * m_parents[p].node[i] + r, m_parents[p].weight[i]);
  Eigen::SparseMatrix<double> out(3 * Eigen::Index(m_parents.size()), 3 * nodes());
  out.setFromTriplets(t.begin(), t.end());  // duplicates (clamped parents) add up
  return out;
}

}  // namespace cloth
