#include "cloth/integrators/xpbd.hpp"

#include <cmath>
#include <vector>

#include "cloth/forces/spring_forces.hpp"

namespace cloth {

namespace {

/// One Gauss-Seidel sweep over every spring of m: moves the predicted positions p towards
/// the compliant constraints; x holds the substep's start positions (for the damping term),
/// lambda the springs' accumulated multipliers (one per slot of each group, group after group,
/// spring_set.hpp), base the first index of each group's.
void project_springs(const Model& m, double hs, Matrix3X& p, const Matrix3X& x, VectorX& lambda,
                     const std::vector<Eigen::Index>& base, Counters& counters) {
  const double c = m.springs.damping;
  for_each_spring(m.springs, [&](int a, int b, size_t g, int s) {
    // the constants of the constraint: alpha~ = 1 / (k hs^2), gamma = alpha~ beta~ / hs
    const double k = m.springs.stiffness(g, s);
    const double alpha_tilde = 1.0 / (k * hs * hs), gamma = c / (k * hs);
    const Vector3 d = p.col(b) - p.col(a);
    const double len = d.norm();
    if (!(len > 0.0)) return;  // coincident ends have no direction
    const Vector3 n = d / len;
    const Vector3 wa = m.inv_mass[a] * m.free.col(a), wb = m.inv_mass[b] * m.free.col(b);
    const double w = (wa + wb).dot(n.cwiseProduct(n));
    if (w == 0.0) return;  // both ends held along the spring
    const double constraint = len - m.springs.rest(g, s);
    const double moved = n.dot((p.col(b) - x.col(b)) - (p.col(a) - x.col(a)));
    double& l = lambda[base[g] + s];
    const double dl =
        (-constraint - alpha_tilde * l - gamma * moved) / ((1.0 + gamma) * w + alpha_tilde);
    l += dl;
    p.col(b) += dl * wb.cwiseProduct(n);
    p.col(a) -= dl * wa.cwiseProduct(n);
    ++counters.constraint_projections;
  });
}

}  // namespace

double xpbd_step(const Model& m, const SolverOptions& o, double h, Matrix3X& x, Matrix3X& v,
                 Matrix3X& p, VectorX& lambda, Counters& counters) {
  const int substeps = o.substeps;
  const double hs = h / substeps;
  // each group's first multiplier: the families' slots, then the list's springs
  std::vector<Eigen::Index> base;
  Eigen::Index slots = 0;
  for (const SpringFamily& fam : m.springs.families) {
    base.push_back(slots);
    slots += fam.slots();
  }
  base.push_back(slots);
  slots += m.springs.list.size();
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
      project_springs(m, hs, p, x, lambda, base, counters);
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
