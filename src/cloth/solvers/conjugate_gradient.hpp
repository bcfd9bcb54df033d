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
  auto dot = [](const Matrix3X& a, const Matrix3X& c) { return (a.array() * c.array()).sum(); };
  x.setZero();
  ws.r = b;
  project(ws.r);
  const double b_norm = std::sqrt(dot(ws.r, ws.r));
  CgResult res;
  if (b_norm == 0.0) return res;
  precondition(ws.r, ws.z);
  project(ws.z);
  ws.p = ws.z;
  double rz = dot(ws.r, ws.z);
  for (int it = 0; it < max_iterations; ++it) {
    apply(ws.p, ws.q);
    project(ws.q);
    const double pq = dot(ws.p, ws.q);
    if (truncate && !(pq > 0.0)) {
      res.negative_curvature = true;
      break;
    }
    res.iterations = it + 1;
    res.relative_residual = std::sqrt(step_and_residual(rz / pq, ws, x)) / b_norm;
    if (res.relative_residual <= tolerance) break;
    precondition(ws.r, ws.z);
    project(ws.z);
    const double rz_new = dot(ws.r, ws.z);
    ws.p = ws.z + (rz_new / rz) * ws.p;
    rz = rz_new;
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
