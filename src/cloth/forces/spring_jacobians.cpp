#include "cloth/forces/spring_jacobians.hpp"

#include "cloth/forces/hinge_bending.hpp"

#include <algorithm>
#include <cmath>

namespace cloth {

namespace {

using Linearized = Eigen::Matrix<double, 4, Eigen::Dynamic, Eigen::RowMajor>;

// springs of the general list per chunk: the chunk's products fit in the first-level cache
constexpr int kChunk = 256;

/// The general list's linearisation into lin and, if out_b is given, the unclamped b.
void linearize_list(const SpringList& l, const Matrix3X& x, bool clamp_compressed, Linearized& lin,
                    double* __restrict out_b) {
  const double* __restrict X = x.row(0).data();
  const double* __restrict Y = x.row(1).data();
  const double* __restrict Z = x.row(2).data();
  const int m = l.size();
  lin.resize(4, m);
  double* __restrict nx = lin.row(0).data();
  double* __restrict ny = lin.row(1).data();
  double* __restrict nz = lin.row(2).data();
  double* __restrict nb = lin.row(3).data();
  const int* __restrict A = l.a.data();
  const int* __restrict B = l.b.data();
  const double* __restrict rest = l.rest.data();
  for (int i = 0; i < m; ++i) {
    const int a = A[i], b = B[i];
    const double dx = X[b] - X[a], dy = Y[b] - Y[a], dz = Z[b] - Z[a];
    const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double il = 1.0 / (len + 1e-300);
    nx[i] = dx * il;
    ny[i] = dy * il;
    nz[i] = dz * il;
    const double t = 1.0 - rest[i] * il;
    nb[i] = clamp_compressed ? std::max(t, 0.0) : t;
    if (out_b) out_b[i] = t;
  }
}

/// y[a] += (bx, by, bz)[i] and y[b] -= the same for the m springs of the list from s0 on.
void scatter(const SpringList& l, int s0, int m, const double* bx, const double* by,
             const double* bz, Matrix3X& y) {
  double* __restrict yx = y.row(0).data();
  double* __restrict yy = y.row(1).data();
  double* __restrict yz = y.row(2).data();
  for (int i = 0; i < m; ++i) {
    const int a = l.a[size_t(s0 + i)], b = l.b[size_t(s0 + i)];
    yx[a] += bx[i];
    yy[a] += by[i];
    yz[a] += bz[i];
    yx[b] -= bx[i];
    yy[b] -= by[i];
    yz[b] -= bz[i];
  }
}

/// The general list's part of add_jacobian_product.
void list_jacobian_product(const SpringList& l, double c, const Linearized& lin, const Matrix3X& u,
                           double alpha, double beta, Matrix3X& y) {
  const double* __restrict U = u.row(0).data();
  const double* __restrict V = u.row(1).data();
  const double* __restrict W = u.row(2).data();
  const double* __restrict nx = lin.row(0).data();
  const double* __restrict ny = lin.row(1).data();
  const double* __restrict nz = lin.row(2).data();
  const double* __restrict nb = lin.row(3).data();
  const int* __restrict A = l.a.data();
  const int* __restrict B = l.b.data();
  const double* __restrict k = l.stiffness.data();
  alignas(64) double bx[kChunk], by[kChunk], bz[kChunk];
  for (int s0 = 0; s0 < l.size(); s0 += kChunk) {
    const int m = std::min(kChunk, l.size() - s0);
    // the grid kernel's block times w = u_b - u_a, spring by spring
#pragma omp simd
    for (int i = 0; i < m; ++i) {
      const int j = s0 + i, a = A[j], b = B[j];
      const double wx = U[b] - U[a], wy = V[b] - V[a], wz = W[b] - W[a];
      const double ak = alpha * k[j];
      const double dw = nx[j] * wx + ny[j] * wy + nz[j] * wz;
      const double s1 = (ak * (1.0 - nb[j]) + beta * c) * dw;
      const double s2 = ak * nb[j];
      bx[i] = s1 * nx[j] + s2 * wx;
      by[i] = s1 * ny[j] + s2 * wy;
      bz[i] = s1 * nz[j] + s2 * wz;
    }
    scatter(l, s0, m, bx, by, bz, y);
  }
}

/// The general list's part of add_newton_product.
void list_newton_product(const SpringList& l, double bc, const Linearized& lk, const Linearized& ld,
                         const Matrix3X& u, double alpha, Matrix3X& y) {
  const double* __restrict U = u.row(0).data();
  const double* __restrict V = u.row(1).data();
  const double* __restrict W = u.row(2).data();
  const double* __restrict nx = lk.row(0).data();
  const double* __restrict ny = lk.row(1).data();
  const double* __restrict nz = lk.row(2).data();
  const double* __restrict nb = lk.row(3).data();
  const double* __restrict mx = ld.row(0).data();
  const double* __restrict my = ld.row(1).data();
  const double* __restrict mz = ld.row(2).data();
  const int* __restrict A = l.a.data();
  const int* __restrict B = l.b.data();
  const double* __restrict k = l.stiffness.data();
  alignas(64) double bx[kChunk], by[kChunk], bz[kChunk];
  for (int s0 = 0; s0 < l.size(); s0 += kChunk) {
    const int m = std::min(kChunk, l.size() - s0);
#pragma omp simd
    for (int i = 0; i < m; ++i) {
      const int j = s0 + i, a = A[j], b = B[j];
      const double wx = U[b] - U[a], wy = V[b] - V[a], wz = W[b] - W[a];
      const double ak = alpha * k[j];
      const double s1 = ak * (1.0 - nb[j]) * (nx[j] * wx + ny[j] * wy + nz[j] * wz);
      const double s2 = ak * nb[j];
      const double s3 = bc * (mx[j] * wx + my[j] * wy + mz[j] * wz);
      bx[i] = s1 * nx[j] + s2 * wx + s3 * mx[j];
      by[i] = s1 * ny[j] + s2 * wy + s3 * my[j];
      bz[i] = s1 * nz[j] + s2 * wz + s3 * mz[j];
    }
    scatter(l, s0, m, bx, by, bz, y);
  }
}

/// One family's linearisation into lin (b clamped or not) and, if out_b is given, the unclamped
/// b into out_b.
void linearize_family(const SpringFamily& fam, const Matrix3X& x, bool clamp_compressed,
                      Eigen::Matrix<double, 4, Eigen::Dynamic, Eigen::RowMajor>& lin,
                      double* __restrict out_b) {
  const int o = fam.offset, m = fam.slots();
  const double* __restrict X = x.row(0).data();
  const double* __restrict Y = x.row(1).data();
  const double* __restrict Z = x.row(2).data();
  lin.resize(4, m);
  double* __restrict nx = lin.row(0).data();
  double* __restrict ny = lin.row(1).data();
  double* __restrict nz = lin.row(2).data();
  double* __restrict nb = lin.row(3).data();
  const double* __restrict mask = fam.mask.data();
  const double* __restrict rest = fam.rest.data();
  for (int p = 0; p < m; ++p) {
    const double dx = X[p + o] - X[p], dy = Y[p + o] - Y[p], dz = Z[p + o] - Z[p];
    const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double il = 1.0 / (len + 1e-300);
    // the mask zeroes the direction, so a slot without a spring adds nothing
    nx[p] = mask[p] * dx * il;
    ny[p] = mask[p] * dy * il;
    nz[p] = mask[p] * dz * il;
    const double b = 1.0 - rest[p] * il;
    nb[p] = mask[p] * (clamp_compressed ? std::max(b, 0.0) : b);
    if (out_b) out_b[p] = mask[p] * b;
  }
}

}  // namespace

void linearize_springs(const SpringSet& springs, const Matrix3X& x, bool clamp_compressed,
                       SpringLinearization& lin, SpringLinearization* unclamped) {
  lin.dirs.resize(springs.groups());
  if (unclamped) unclamped->dirs.resize(springs.groups());
  // the general list, the last group, in the same way
  const size_t g = springs.families.size();
  if (!unclamped) {
    linearize_list(springs.list, x, clamp_compressed, lin.dirs[g], nullptr);
  } else {
    auto& u = unclamped->dirs[g];
    u.resize(4, springs.list.size());
    linearize_list(springs.list, x, clamp_compressed, lin.dirs[g], u.row(3).data());
    u.topRows<3>() = lin.dirs[g].topRows<3>();
  }
  for (size_t fi = 0; fi < springs.families.size(); ++fi) {
    const SpringFamily& fam = springs.families[fi];
    if (!unclamped) {
      linearize_family(fam, x, clamp_compressed, lin.dirs[fi], nullptr);
      continue;
    }
    // the same directions, b as it is: one pass over the springs for both
    auto& u = unclamped->dirs[fi];
    u.resize(4, fam.slots());
    linearize_family(fam, x, clamp_compressed, lin.dirs[fi], u.row(3).data());
    u.topRows<3>() = lin.dirs[fi].topRows<3>();
  }
}

void add_jacobian_product(const SpringSet& springs, const SpringLinearization& lin,
                          const Matrix3X& u, double alpha, double beta, Matrix3X& y,
                          Matrix3X& buf) {
  const double c = springs.damping;
  const double* __restrict U = u.row(0).data();
  const double* __restrict V = u.row(1).data();
  const double* __restrict W = u.row(2).data();
  double* __restrict bx = buf.row(0).data();
  double* __restrict by = buf.row(1).data();
  double* __restrict bz = buf.row(2).data();
  for (size_t fi = 0; fi < springs.families.size(); ++fi) {
    const SpringFamily& fam = springs.families[fi];
    const int o = fam.offset, m = fam.slots();
    const auto& L = lin.dirs[fi];
    const double* __restrict nx = L.row(0).data();
    const double* __restrict ny = L.row(1).data();
    const double* __restrict nz = L.row(2).data();
    const double* __restrict nb = L.row(3).data();
    const double ak = alpha * fam.stiffness;
    // block times the relative vector w = u_q - u_p, for the anchor p
    for (int p = 0; p < m; ++p) {
      const double wx = U[p + o] - U[p], wy = V[p + o] - V[p], wz = W[p + o] - W[p];
      const double dw = nx[p] * wx + ny[p] * wy + nz[p] * wz;
      const double s1 = (ak * (1.0 - nb[p]) + beta * c) * dw;
      // a slot without a spring has d^ = 0 and b = 0, so s2 vanishes there too
      const double s2 = ak * nb[p];
      bx[p] = s1 * nx[p] + s2 * wx;
      by[p] = s1 * ny[p] + s2 * wy;
      bz[p] = s1 * nz[p] + s2 * wz;
    }
    for (int r = 0; r < 3; ++r) {
      y.row(r).head(m) += buf.row(r).head(m);
      y.row(r).segment(o, m) -= buf.row(r).head(m);
    }
  }
  if (!springs.list.empty())
    list_jacobian_product(springs.list, c, lin.dirs.back(), u, alpha, beta, y);
  add_bending_product(springs.bending, u, alpha, y);
}

void add_newton_product(const SpringSet& springs, const SpringLinearization& lin_k,
                        const SpringLinearization& lin_d, const Matrix3X& u, double alpha,
                        double beta, Matrix3X& y, Matrix3X& buf) {
  const double bc = beta * springs.damping;
  const double* __restrict U = u.row(0).data();
  const double* __restrict V = u.row(1).data();
  const double* __restrict W = u.row(2).data();
  double* __restrict bx = buf.row(0).data();
  double* __restrict by = buf.row(1).data();
  double* __restrict bz = buf.row(2).data();
  for (size_t fi = 0; fi < springs.families.size(); ++fi) {
    const SpringFamily& fam = springs.families[fi];
    const int o = fam.offset, m = fam.slots();
    const auto& L = lin_k.dirs[fi];
    const auto& L0 = lin_d.dirs[fi];
    const double* __restrict nx = L.row(0).data();
    const double* __restrict ny = L.row(1).data();
    const double* __restrict nz = L.row(2).data();
    const double* __restrict nb = L.row(3).data();
    const double* __restrict mx = L0.row(0).data();
    const double* __restrict my = L0.row(1).data();
    const double* __restrict mz = L0.row(2).data();
    const double ak = alpha * fam.stiffness;
    for (int p = 0; p < m; ++p) {
      const double wx = U[p + o] - U[p], wy = V[p + o] - V[p], wz = W[p + o] - W[p];
      // stiffness along d^ and across it, damping along the step's first direction d0^
      const double s1 = ak * (1.0 - nb[p]) * (nx[p] * wx + ny[p] * wy + nz[p] * wz);
      const double s2 = ak * nb[p];
      const double s3 = bc * (mx[p] * wx + my[p] * wy + mz[p] * wz);
      bx[p] = s1 * nx[p] + s2 * wx + s3 * mx[p];
      by[p] = s1 * ny[p] + s2 * wy + s3 * my[p];
      bz[p] = s1 * nz[p] + s2 * wz + s3 * mz[p];
    }
    for (int r = 0; r < 3; ++r) {
      y.row(r).head(m) += buf.row(r).head(m);
      y.row(r).segment(o, m) -= buf.row(r).head(m);
    }
  }
  if (!springs.list.empty())
    list_newton_product(springs.list, bc, lin_k.dirs.back(), lin_d.dirs.back(), u, alpha, y);
  add_bending_product(springs.bending, u, alpha, y);
}

void add_jacobian_diagonal(const SpringSet& springs, const SpringLinearization& lin, double alpha,
                           double beta, Matrix3X& diag, Matrix3X& buf) {
  const double c = springs.damping;
  for (size_t fi = 0; fi < springs.families.size(); ++fi) {
    const SpringFamily& fam = springs.families[fi];
    const int o = fam.offset, m = fam.slots();
    const auto& L = lin.dirs[fi];
    const double ak = alpha * fam.stiffness;
    // both ends of a spring see -J and -c d^ d^T on their diagonal block
    for (int r = 0; r < 3; ++r) {
      for (int p = 0; p < m; ++p) {
        const double n2 = L(r, p) * L(r, p);
        const double present = fam.mask[p];
        buf(r, p) = -(ak * ((1.0 - L(3, p)) * n2 + L(3, p)) + beta * c * n2) * present;
      }
      diag.row(r).head(m) += buf.row(r).head(m);
      diag.row(r).segment(o, m) += buf.row(r).head(m);
    }
  }
  add_bending_diagonal(springs.bending, alpha, diag);
  // the general list: the same block on both ends' diagonals
  const SpringList& l = springs.list;
  if (l.empty()) return;
  const Linearized& L = lin.dirs.back();
  for (int i = 0; i < l.size(); ++i) {
    const double ak = alpha * l.stiffness[size_t(i)];
    for (int r = 0; r < 3; ++r) {
      const double n2 = L(r, i) * L(r, i);
      const double e = -(ak * ((1.0 - L(3, i)) * n2 + L(3, i)) + beta * c * n2);
      diag(r, l.a[size_t(i)]) += e;
      diag(r, l.b[size_t(i)]) += e;
    }
  }
}

}  // namespace cloth
