#pragma once
/// @file trust_region_cg.hpp
/// Steihaug and Toint's truncated conjugate gradient for a trust-region subproblem: minimise
/// the quadratic model m(s) = -b.s + 1/2 s.A s over |s|_W <= radius, with A symmetric but
/// possibly indefinite. CG runs as usual from s = 0 until it converges, leaves the region (it
/// stops on the region's edge along its direction) or meets a direction of non-positive
/// curvature (it follows that direction to the edge, where the model keeps falling). Every
/// vector is multiplied by the filter S as in conjugate_gradient.hpp.
///
/// W is a diagonal weight (the mass norm |s|_M^2 = sum_p m_p |s_p|^2 in implicit Euler), not
/// the preconditioner's norm: CG's iterates grow monotonically only in the latter, so an iterate
/// may leave the region and a later one re-enter it; stopping at the first crossing still
/// lowers the model at least as much as the first (preconditioned steepest-descent) step cut
/// to the region, which is what the trust-region method's convergence needs.

#include <cmath>

#include "cloth/model/types.hpp"
#include "cloth/solvers/conjugate_gradient.hpp"

namespace cloth {

/// Outcome of one trust-region solve.
struct TrustRegionCgResult {
  int iterations = 0;               // products with A that moved s
  double relative_residual = 0;     // |S r| / |S b| at the last interior iterate
  bool negative_curvature = false;  // met a direction p with p^T A p <= 0
  bool on_boundary = false;         // s ends on the region's edge
  double predicted_decrease = 0;    // -m(s) = b.s - 1/2 s.A s, >= 0
};

/// The tau >= 0 with |x + tau p|_W = radius, for |x|_W <= radius.
/// @param w  3 by #P weights of the norm (positive where p may be nonzero)
inline double distance_to_boundary(const Matrix3X& x, const Matrix3X& p, const Matrix3X& w,
                                   double radius) {
  const double pp = (p.array().square() * w.array()).sum();
  const double xp = (x.array() * p.array() * w.array()).sum();
  const double xx = (x.array().square() * w.array()).sum();
  if (!(pp > 0.0)) return 0.0;
  // the positive root of pp tau^2 + 2 xp tau + (xx - radius^2) = 0, in the stable form
  const double c = std::max(radius * radius - xx, 0.0);
  const double disc = std::sqrt(xp * xp + pp * c);
  return xp >= 0.0 ? c / (xp + disc) : (disc - xp) / pp;
}

/// Solves the trust-region subproblem min m(s), |s|_W <= radius, approximately.
/// @param apply         apply(u, out): out = A u, both 3 by #P
/// @param precondition  precondition(r, z): z = P^-1 r, P symmetric positive definite
/// @param project       project(u): u = S u in place
/// @param b             3 by #P, minus the model's gradient at s = 0
/// @param w             3 by #P weights of the region's norm
/// @param radius        the region's radius in that norm (> 0)
/// @param s             3 by #P step, written
/// @param tolerance     relative residual |S r| / |S b| at which an interior solve stops
template <class Apply, class Precondition, class Project>
TrustRegionCgResult trust_region_pcg(Apply&& apply, Precondition&& precondition, Project&& project,
                                     const Matrix3X& b, const Matrix3X& w, double radius,
                                     Matrix3X& s, CgWorkspace& ws, double tolerance,
                                     int max_iterations) {
  double b_norm = 0.0;
  double rz = start_pcg(precondition, project, b, s, ws, b_norm);
  TrustRegionCgResult res;
  if (b_norm == 0.0) return res;
  // the model at s: m(s_k) = -1/2 b.s_k for CG's iterates (r_k is orthogonal to s_k)
  double model = 0.0;
  for (int it = 0; it < max_iterations; ++it) {
    apply(ws.p, ws.q);
    project(ws.q);
    const double pq = cg_dot(ws.p, ws.q);
    const double alpha = pq > 0.0 ? rz / pq : 0.0;
    // out of the region, or curving down: to the edge along p, where the model is
    // m(s + tau p) = m(s) - tau r.p + 1/2 tau^2 p.A p
    ws.z = s + alpha * ws.p;
    const bool leaves = (ws.z.array().square() * w.array()).sum() >= radius * radius;
    if (!(pq > 0.0) || leaves) {
      const double tau = distance_to_boundary(s, ws.p, w, radius);
      model += -tau * cg_dot(ws.r, ws.p) + 0.5 * tau * tau * pq;
      s += tau * ws.p;
      res.negative_curvature = !(pq > 0.0);
      res.on_boundary = true;
      res.iterations = it + 1;
      break;
    }
    res.iterations = it + 1;
    res.relative_residual = std::sqrt(step_and_residual(alpha, ws, s)) / b_norm;
    model = -0.5 * cg_dot(b, s);
    if (res.relative_residual <= tolerance) break;
    rz = next_direction(precondition, project, ws, rz);
  }
  res.predicted_decrease = -model;
  return res;
}

}  // namespace cloth
