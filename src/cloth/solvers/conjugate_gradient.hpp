#pragma once
/// @file conjugate_gradient.hpp
/// Preconditioned conjugate gradient with a constraint filter (Baraff and Witkin 1998, 5.3):
/// every vector is multiplied by the filter S, so held axes of the solution stay exactly zero.

#include <cmath>

#include "cloth/model/types.hpp"

namespace cloth {

/// Outcome of one solve.
struct CgResult {
  int iterations = 0;
  double relative_residual = 0;     // |S r| / |S b|
  bool negative_curvature = false;  // truncate: stopped at a direction p with p^T A p <= 0
};

/// Work vectors, allocated once (each 3 by #P).
struct CgWorkspace {
  Matrix3X r, z, p, q;
  void resize(Eigen::Index n) {
    r.resize(3, n);
    z.resize(3, n);
    p.resize(3, n);
    q.resize(3, n);
  }
};

/// x += alpha p and r -= alpha q in one pass over the vectors; returns |r|^2 after it.
inline double step_and_residual(double alpha, CgWorkspace& ws, Matrix3X& x) {
  double* __restrict xd = x.data();
  double* __restrict rd = ws.r.data();
  const double* __restrict pd = ws.p.data();
  const double* __restrict qd = ws.q.data();
  double rr = 0.0;
  const Eigen::Index n = x.size();
#pragma omp simd reduction(+ : rr)
  for (Eigen::Index i = 0; i < n; ++i) {
    xd[i] += alpha * pd[i];
    rd[i] -= alpha * qd[i];
    rr += rd[i] * rd[i];
  }
  return rr;
}

/// The sum of the entrywise products of two 3 by #P vectors.
inline double cg_dot(const Matrix3X& a, const Matrix3X& c) {
  return (a.array() * c.array()).sum();
}

/// CG's start from x = 0: r = S b, z = S P^-1 r, p = z. Returns r.z; b_norm = |S b|, and when
/// it is 0 nothing else is set (x = 0 solves the system).
template <class Precondition, class Project>
double start_pcg(Precondition&& precondition, Project&& project, const Matrix3X& b, Matrix3X& x,
                 CgWorkspace& ws, double& b_norm) {
  x.setZero();
  ws.r = b;
  project(ws.r);
  b_norm = std::sqrt(cg_dot(ws.r, ws.r));
  if (b_norm == 0.0) return 0.0;
  precondition(ws.r, ws.z);
  project(ws.z);
  ws.p = ws.z;
  return cg_dot(ws.r, ws.z);
}

/// CG's next direction after r was updated: z = S P^-1 r, p = z + (r.z / rz) p. Returns the
/// new r.z.
template <class Precondition, class Project>
double next_direction(Precondition&& precondition, Project&& project, CgWorkspace& ws, double rz) {
  precondition(ws.r, ws.z);
  project(ws.z);
  const double rz_new = cg_dot(ws.r, ws.z);
  ws.p = ws.z + (rz_new / rz) * ws.p;
  return rz_new;
}

/// Solves S A S x = S b for symmetric positive definite A given as a product, with S an
/// orthogonal projection applied in place.
/// @param apply         apply(u, out): out = A u, both 3 by #P
/// @param precondition  precondition(r, z): z = P^-1 r, both 3 by #P, P symmetric positive
///                      definite; z is projected afterwards
/// @param project       project(u): u = S u in place, 3 by #P
/// @param b             3 by #P right-hand side
/// @param x             3 by #P solution, starts at zero
/// @param truncate      stop at the first direction p with p^T A p <= 0 (A indefinite), leaving
///                      x at the last iterate, which lowered the quadratic model (truncated Newton)
template <class Apply, class Precondition, class Project>
CgResult projected_pcg(Apply&& apply, Precondition&& precondition, Project&& project,
                       const Matrix3X& b, Matrix3X& x, CgWorkspace& ws, double tolerance,
                       int max_iterations, bool truncate = false) {
  double b_norm = 0.0;
  double rz = start_pcg(precondition, project, b, x, ws, b_norm);
  CgResult res;
  if (b_norm == 0.0) return res;
  for (int it = 0; it < max_iterations; ++it) {
    apply(ws.p, ws.q);
    project(ws.q);
    const double pq = cg_dot(ws.p, ws.q);
    if (truncate && !(pq > 0.0)) {
      res.negative_curvature = true;
      break;
    }
    res.iterations = it + 1;
    res.relative_residual = std::sqrt(step_and_residual(rz / pq, ws, x)) / b_norm;
    if (res.relative_residual <= tolerance) break;
    rz = next_direction(precondition, project, ws, rz);
  }
  return res;
}

/// The same with S the held-axis mask.
/// @param filter  3 by #P, 1 for free axes, 0 for held ones; precondition must keep held axes
///                zero
template <class Apply, class Precondition>
CgResult filtered_pcg_with(Apply&& apply, Precondition&& precondition, const Matrix3X& b,
                           const Matrix3X& filter, Matrix3X& x, CgWorkspace& ws, double tolerance,
                           int max_iterations) {
  auto mask = [&](Matrix3X& u) { u.array() *= filter.array(); };
  return projected_pcg(apply, precondition, mask, b, x, ws, tolerance, max_iterations);
}

/// The same with the Jacobi preconditioner.
/// @param inv_diag  3 by #P inverse of A's diagonal
template <class Apply>
CgResult filtered_pcg(Apply&& apply, const Matrix3X& b, const Matrix3X& inv_diag,
                      const Matrix3X& filter, Matrix3X& x, CgWorkspace& ws, double tolerance,
                      int max_iterations) {
  auto jacobi = [&](const Matrix3X& r, Matrix3X& z) { z = r.cwiseProduct(inv_diag); };
  return filtered_pcg_with(apply, jacobi, b, filter, x, ws, tolerance, max_iterations);
}

}  // namespace cloth
