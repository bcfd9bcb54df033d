#include "cloth/integrators/xpbd.hpp"

#include <cmath>

#include "cloth/forces/spring_forces.hpp"

namespace cloth {

namespace {

/// The constants of one family's constraints in a substep of hs seconds.
struct Compliance {
  double alpha_tilde = 0;  // 1 / (k hs^2)
  double gamma = 0;        // alpha_tilde beta_tilde / hs = c / (k hs)
};

/// One Gauss-Seidel sweep over every spring of m: moves the predicted positions p towards
/// the compliant constraints; x holds the substep's start positions (for the damping term),
/// lambda the springs' accumulated multipliers (one per anchor slot, family after family).
void project_springs(const Model& m, double hs, Matrix3X& p, const Matrix3X& x, VectorX& lambda,
                     Counters& counters) {
  const double c = m.springs.damping;
  Eigen::Index base = 0;
  for (const SpringFamily& fam : m.springs.families) {
    const int o = fam.offset, slots = fam.slots();
    const Compliance comp{1.0 / (fam.stiffness * hs * hs), c / (fam.stiffness * hs)};
    for (int a = 0; a < slots; ++a) {
      if (fam.mask[a] == 0.0) continue;
      const int b = a + o;
      const Vector3 d = p.col(b) - p.col(a);
      const double len = d.norm();
      if (!(len > 0.0)) continue;  // coincident ends have no direction
      const Vector3 n = d / len;
      const Vector3 wa = m.inv_mass[a] * m.free.col(a), wb = m.inv_mass[b] * m.free.col(b);
      const double w = (wa + wb).dot(n.cwiseProduct(n));
      if (w == 0.0) continue;  // both ends held along the spring
      const double constraint = len - fam.rest[a];
      const double moved = n.dot((p.col(b) - x.col(b)) - (p.col(a) - x.col(a)));
      double& l = lambda[base + a];
      const double dl = (-constraint - comp.alpha_tilde * l - comp.gamma * moved) /
                        ((1.0 + comp.gamma) * w + comp.alpha_tilde);
      l += dl;
      p.col(b) += dl * wb.cwiseProduct(n);
      p.col(a) -= dl * wa.cwiseProduct(n);
      ++counters.constraint_projections;
    }
    base += slots;
  }
}

}  // namespace

double xpbd_step(const Model& m, const SolverOptions& o, double h, Matrix3X& x, Matrix3X& v,
                 Matrix3X& p, VectorX& lambda, Counters& counters) {
  const int substeps = o.substeps;
  const double hs = h / substeps;
  Eigen::Index slots = 0;
  for (const SpringFamily& fam : m.springs.families) slots += fam.slots();
  lambda.resize(slots);  // a no-op after the first step
  double dissipated = 0.0;
  for (int s = 0; s < substeps; ++s) {
    // gravity explicit, air drag implicit (m v' = m (v0 + hs g) - hs drag (v' - wind)) on
    // free axes; a held axis keeps its velocity (zero, or a handle's path velocity)
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      const double a = hs * m.air_drag * m.inv_mass[i];
      const Vector3 moved = (v.col(i) + hs * m.gravity + a * m.wind) / (1.0 + a);
      v.col(i) = m.free.col(i).cwiseProduct(moved) +
                 (Vector3::Ones() - m.free.col(i)).cwiseProduct(v.col(i));
    }
    p = x + hs * v;
    lambda.setZero();
    for (int it = 0; it < o.iterations; ++it) {
      project_springs(m, hs, p, x, lambda, counters);
      ++counters.force_evals;  // one sweep over every spring: the work of a force evaluation
    }
    // a held axis moved exactly by its velocity in the prediction and no projection moves it
    // (zero inverse mass), so x and v stay exact there
    v = (p - x) / hs;
    x = p;
    dissipated += hs * (damping_power(m.springs, x, v) + m.drag_power(v));
  }
  return dissipated;
}

}  // namespace cloth
