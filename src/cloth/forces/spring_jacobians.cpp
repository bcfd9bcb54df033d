#include "cloth/forces/spring_jacobians.hpp"

#include <cmath>

namespace cloth {

namespace {

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
  lin.dirs.resize(springs.families.size());
  if (unclamped) unclamped->dirs.resize(springs.families.size());
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
}

}  // namespace cloth
