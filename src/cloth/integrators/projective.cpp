#include "cloth/integrators/projective.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>

#include "cloth/forces/spring_forces.hpp"

namespace cloth {

/// The matrix of one held-axis pattern: M / h^2 + L with every held row and column replaced
/// by the identity's, factorised; and the full matrix's columns of the held entries, which
/// move the held positions' pull to the right-hand side.
struct ProjectiveSolver::Factor {
  VectorX free;                          // #P: 1 where the axis moves
  Eigen::SparseMatrix<double> coupling;  // full matrix, held columns only
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
};

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

/// Entries of (M / h^2 + drag / h) + L, L the graph Laplacian of the springs weighted by
/// k + c / h (stiffness, and the isotropic part of the dampers).
Triplets system_entries(const Model& m, double h) {
  Triplets t;
  for (Eigen::Index i = 0; i < m.mass.size(); ++i)
    t.emplace_back(int(i), int(i), m.mass[i] / (h * h) + m.air_drag / h);
  for_each_spring(m.springs, [&](int a, int b, size_t g, int s) {
    const double k = m.springs.stiffness(g, s) + m.springs.damping / h;
    t.emplace_back(a, a, k);
    t.emplace_back(b, b, k);
    t.emplace_back(a, b, -k);
    t.emplace_back(b, a, -k);
  });
  return t;
}

}  // namespace

ProjectiveSolver::ProjectiveSolver(const Model& m) {
  for (Matrix3X* s : {&m_x0, &m_y, &m_rhs}) s->setZero(3, m.particle_count());
  for (VectorX* s : {&m_held, &m_b, &m_solution}) s->setZero(m.particle_count());
}

ProjectiveSolver::~ProjectiveSolver() = default;

void ProjectiveSolver::factorise(const Model& m, double h) {
  m_factors.clear();
  const Triplets all = system_entries(m, h);
  const int n = m.particle_count();
  for (int r = 0; r < 3; ++r) {
    const VectorX free = m.free.row(r).transpose();
    int found = -1;
    for (size_t f = 0; f < m_factors.size(); ++f)
      if (m_factors[f]->free == free) found = int(f);
    if (found >= 0) {
      m_factor_of_axis[r] = found;
      continue;
    }
    auto f = std::make_unique<Factor>();
    f->free = free;
    Triplets kept, coupling;
    for (const auto& e : all) {
      const bool row_free = free[e.row()] > 0, col_free = free[e.col()] > 0;
      if (row_free && col_free) kept.push_back(e);
      if (!col_free) coupling.push_back(e);
    }
    for (int i = 0; i < n; ++i)
      if (free[i] == 0.0) kept.emplace_back(i, i, 1.0);
    Eigen::SparseMatrix<double> a(n, n);
    a.setFromTriplets(kept.begin(), kept.end());
    f->coupling.resize(n, n);
    f->coupling.setFromTriplets(coupling.begin(), coupling.end());
    f->ldlt.compute(a);
    m_factor_of_axis[r] = int(m_factors.size());
    m_factors.push_back(std::move(f));
  }
  m_h = h;
}

void ProjectiveSolver::add_velocity_forces(const Model& m, double h, const Matrix3X& x,
                                           Matrix3X& rhs) const {
  // The damper force -c/h n n^T (du_b - du_a) (du = x - x0, n frozen at x0) is split into an
  // isotropic part -c/h (du_b - du_a), which sits in the matrix, and the transverse rest
  // c/h (I - n n^T)(du_b - du_a), lagged here: a positive semidefinite remainder smaller than
  // the matrix's part, so the lagged iteration contracts whatever the damping.
  const double ch = m.springs.damping / h;
  if (ch != 0.0) {
    for_each_spring(m.springs, [&](int a, int b, size_t, int) {
      const Vector3 d0 = m_x0.col(b) - m_x0.col(a);
      const Vector3 n = d0.normalized();
      const Vector3 du = (x.col(b) - m_x0.col(b)) - (x.col(a) - m_x0.col(a));
      const Vector3 pull = ch * (d0 + du - n * n.dot(du));
      rhs.col(b) += pull;
      rhs.col(a) -= pull;
    });
  }
  // air drag -drag ((x - x0) / h - wind): implicit in the matrix's diagonal
  if (m.air_drag != 0.0) {
    rhs += (m.air_drag / h) * m_x0;
    if (!m.wind.isZero()) rhs.colwise() += m.air_drag * m.wind;
  }
}

void ProjectiveSolver::add_projections(const Model& m, const Matrix3X& x, Matrix3X& rhs) const {
  for_each_spring(m.springs, [&](int a, int b, size_t g, int s) {
    const Vector3 d = x.col(b) - x.col(a);
    const double len = d.norm();
    if (!(len > 0.0)) return;
    const Vector3 kd = m.springs.stiffness(g, s) * m.springs.rest(g, s) / len * d;
    rhs.col(b) += kd;
    rhs.col(a) -= kd;
  });
}

double ProjectiveSolver::step(const Model& m, const SolverOptions& o, double h, Matrix3X& x,
                              Matrix3X& v, Counters& counters) {
  if (h != m_h) factorise(m, h);
  m_x0 = x;
  // the prediction; a held axis (zero velocity, no gravity) stays where it is
  m_y = x + h * v;
  for (int r = 0; r < 3; ++r) m_y.row(r) += (h * h * m.gravity[r]) * m.free.row(r);
  const double inv_h2 = 1.0 / (h * h);
  x = m_y;
  for (int it = 0; it < o.iterations; ++it) {
    for (int r = 0; r < 3; ++r)
      m_rhs.row(r) = (inv_h2 * m_y.row(r)).cwiseProduct(m.mass.transpose());
    add_projections(m, x, m_rhs);
    add_velocity_forces(m, h, x, m_rhs);
    ++counters.force_evals;  // the local step: one pass over every spring
    for (int r = 0; r < 3; ++r) {
      const Factor& f = *m_factors[size_t(m_factor_of_axis[r])];
      // the held entries' pull moves to the right-hand side; their rows are the identity's
      m_held = m_y.row(r).transpose().cwiseProduct(VectorX::Ones(x.cols()) - f.free);
      m_b.noalias() = f.coupling * m_held;
      m_b = m_rhs.row(r).transpose() - m_b;
      for (Eigen::Index i = 0; i < m_b.size(); ++i)
        if (f.free[i] == 0.0) m_b[i] = m_y(r, i);
      m_solution = f.ldlt.solve(m_b);
      x.row(r) = m_solution.transpose();
    }
    ++counters.linear_solves;
  }
  v = (x - m_x0) / h;
  return h * (damping_power(m.springs, x, v) + m.drag_power(v));
}

}  // namespace cloth
