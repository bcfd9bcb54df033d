#include "cloth/forces/spring_forces.hpp"

#include <cmath>
#include <limits>

namespace cloth {

namespace {

// keeps 1/|d| finite for coincident particles without changing any normal length
constexpr double kTinyLength = 1e-300;

}  // namespace

double add_spring_forces(const SpringSet& springs, const Matrix3X& x, const Matrix3X& v,
                         Matrix3X& f, Matrix3X& buf) {
  const double c = springs.damping;
  const double* __restrict X = x.row(0).data();
  const double* __restrict Y = x.row(1).data();
  const double* __restrict Z = x.row(2).data();
  const double* __restrict U = v.row(0).data();
  const double* __restrict V = v.row(1).data();
  const double* __restrict W = v.row(2).data();
  double* __restrict bx = buf.row(0).data();
  double* __restrict by = buf.row(1).data();
  double* __restrict bz = buf.row(2).data();
  double power = 0.0;
  for (const SpringFamily& fam : springs.families) {
    const int o = fam.offset, m = fam.slots();
    const double k = fam.stiffness;
    const double* __restrict mask = fam.mask.data();
    const double* __restrict rest = fam.rest.data();
    // force on the anchor p from the spring to p + o, one contiguous branch-free pass
#pragma omp simd reduction(+ : power)
    for (int p = 0; p < m; ++p) {
      const double dx = X[p + o] - X[p], dy = Y[p + o] - Y[p], dz = Z[p + o] - Z[p];
      const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
      const double il = 1.0 / (len + kTinyLength);
      const double vr =
          ((U[p + o] - U[p]) * dx + (V[p + o] - V[p]) * dy + (W[p + o] - W[p]) * dz) * il;
      const double s = mask[p] * (k * (len - rest[p]) + c * vr) * il;
      bx[p] = s * dx;
      by[p] = s * dy;
      bz[p] = s * dz;
      power += mask[p] * c * vr * vr;
    }
    // the anchor gains the force, the partner loses it (Newton's third law)
    for (int r = 0; r < 3; ++r) {
      f.row(r).head(m) += buf.row(r).head(m);
      f.row(r).segment(o, m) -= buf.row(r).head(m);
    }
  }
  return power;
}

double damping_power(const SpringSet& springs, const Matrix3X& x, const Matrix3X& v) {
  const double c = springs.damping;
  if (c == 0.0) return 0.0;
  double power = 0.0;
  for (const SpringFamily& fam : springs.families) {
    const int o = fam.offset, m = fam.slots();
    for (int p = 0; p < m; ++p) {
      const Vector3 d = x.col(p + o) - x.col(p);
      const double vr = (v.col(p + o) - v.col(p)).dot(d) / (d.norm() + kTinyLength);
      power += fam.mask[p] * c * vr * vr;
    }
  }
  return power;
}

double elastic_energy(const SpringSet& springs, const Matrix3X& x) {
  double e = 0.0;
  for (const SpringFamily& fam : springs.families) {
    const int o = fam.offset, m = fam.slots();
    double ef = 0.0;
    for (int p = 0; p < m; ++p) {
      const double stretch = (x.col(p + o) - x.col(p)).norm() - fam.rest[p];
      ef += fam.mask[p] * stretch * stretch;
    }
    e += 0.5 * fam.stiffness * ef;
  }
  return e;
}

StrainStats strain_stats(const SpringSet& springs, const Matrix3X& x) {
  StrainStats s;
  double sum = 0.0;
  int count = 0;
  bool nan = false;
  for (const SpringFamily& fam : springs.families) {
    const int o = fam.offset, m = fam.slots();
    for (int p = 0; p < m; ++p) {
      if (fam.mask[p] == 0.0) continue;
      const double e = std::abs((x.col(p + o) - x.col(p)).norm() / fam.rest[p] - 1.0);
      nan = nan || !std::isfinite(e);
      s.max_abs = std::max(s.max_abs, e);
      sum += e;
      ++count;
    }
  }
  if (nan)
    return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  s.mean_abs = count > 0 ? sum / count : 0.0;
  return s;
}

}  // namespace cloth

namespace cloth {

bool within_strain(const SpringSet& springs, const Matrix3X& x, double limit) {
  // |d| / l0 - 1 in [-limit, limit]  <=>  (1 - limit)^2 l0^2 <= |d|^2 <= (1 + limit)^2 l0^2;
  // written so that a NaN fails the test
  const double hi = (1.0 + limit) * (1.0 + limit);
  const double lo = limit < 1.0 ? (1.0 - limit) * (1.0 - limit) : 0.0;
  const double* __restrict X = x.row(0).data();
  const double* __restrict Y = x.row(1).data();
  const double* __restrict Z = x.row(2).data();
  int bad = 0;
  for (const SpringFamily& fam : springs.families) {
    const int o = fam.offset, m = fam.slots();
    const double* __restrict mask = fam.mask.data();
    const double* __restrict rest = fam.rest.data();
#pragma omp simd reduction(+ : bad)
    for (int p = 0; p < m; ++p) {
      const double dx = X[p + o] - X[p], dy = Y[p + o] - Y[p], dz = Z[p + o] - Z[p];
      const double d2 = dx * dx + dy * dy + dz * dz;
      const double r2 = rest[p] * rest[p];
      const bool ok = (d2 <= hi * r2) && (d2 >= lo * r2);
      bad += (mask[p] != 0.0 && !ok) ? 1 : 0;
    }
  }
  // a single particle without springs is checked for finiteness directly
  return bad == 0 && x.allFinite();
}

}  // namespace cloth
