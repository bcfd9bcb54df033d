#include "cloth/forces/spring_forces.hpp"

#include "cloth/forces/hinge_bending.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace cloth {

namespace {

// keeps 1/|d| finite for coincident particles without changing any normal length
constexpr double kTinyLength = 1e-300;

// springs of the general list computed together: a block's forces stay in registers
constexpr int kBlock = 16;

/// The general list's arrays, as raw pointers for the kernels below.
struct ListArrays {
  const double *X, *Y, *Z, *U, *V, *W;  // positions and velocities, by axis
  double *fx, *fy, *fz;                 // forces, by axis
  const int *A, *B;                     // ends
  const double *rest, *k;               // rest lengths and stiffnesses
  double c;                             // damping
};

/// Adds (or with kSubtract subtracts) the block's forces bx, by, bz to the particles idx[i],
/// which with kRun are the consecutive particles i0 + i, updated as contiguous vectors.
template <bool kRun, bool kSubtract, class Count>
void scatter_block(const ListArrays& p, const int* __restrict idx, int i0, Count m,
                   const double* __restrict bx, const double* __restrict by,
                   const double* __restrict bz) {
  double* __restrict fx = p.fx;
  double* __restrict fy = p.fy;
  double* __restrict fz = p.fz;
  const double s = kSubtract ? -1.0 : 1.0;
  if (kRun) {
#pragma omp simd
    for (int i = 0; i < m; ++i) {
      fx[i0 + i] += s * bx[i];
      fy[i0 + i] += s * by[i];
      fz[i0 + i] += s * bz[i];
    }
  } else {
    // (ends may repeat within a block: one at a time)
    for (int i = 0; i < m; ++i) {
      fx[idx[i]] += s * bx[i];
      fy[idx[i]] += s * by[i];
      fz[idx[i]] += s * bz[i];
    }
  }
}

/// Forces of the springs s0 .. s0 + m - 1: computed together (vectorisable: no stores to
/// particles), then added to both ends. With kRunA (kRunB) their first (second) ends are the
/// consecutive particles A[s0] + i (B[s0] + i), loaded and updated as contiguous vectors (the
/// layout renumbered() gives most blocks); m a compile-time constant keeps the block in
/// registers. Each spring's dissipated power is added to its lane of power (kBlock lanes), so
/// no block ends in a horizontal sum.
template <bool kRunA, bool kRunB, class Count>
void list_force_block(const ListArrays& p, int s0, Count m, double* __restrict power) {
  const double* __restrict X = p.X;
  const double* __restrict Y = p.Y;
  const double* __restrict Z = p.Z;
  const double* __restrict U = p.U;
  const double* __restrict V = p.V;
  const double* __restrict W = p.W;
  const int* __restrict A = p.A + s0;
  const int* __restrict B = p.B + s0;
  const double* __restrict rest = p.rest + s0;
  const double* __restrict k = p.k + s0;
  const double c = p.c;
  const int a0 = A[0], b0 = B[0];
  double bx[kBlock], by[kBlock], bz[kBlock];
  // the same expression as the grid kernel's, spring by spring, the whole block at once (16
  // lanes ran 1.1x faster than 8 and 1.25x faster than 4 in bench_cloth's BM_spring_paths)
#pragma omp simd simdlen(kBlock)
  for (int i = 0; i < m; ++i) {
    const int a = kRunA ? a0 + i : A[i], b = kRunB ? b0 + i : B[i];
    const double dx = X[b] - X[a], dy = Y[b] - Y[a], dz = Z[b] - Z[a];
    const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double il = 1.0 / (len + kTinyLength);
    const double vr = ((U[b] - U[a]) * dx + (V[b] - V[a]) * dy + (W[b] - W[a]) * dz) * il;
    const double sc = (k[i] * (len - rest[i]) + c * vr) * il;
    bx[i] = sc * dx;
    by[i] = sc * dy;
    bz[i] = sc * dz;
    power[i] += c * vr * vr;
  }
  // end a gains the force, end b loses it
  scatter_block<kRunA, false>(p, A, a0, m, bx, by, bz);
  scatter_block<kRunB, true>(p, B, b0, m, bx, by, bz);
}

/// True when idx[0 .. kBlock) are consecutive integers.
inline bool is_run(const int* idx) {
  bool run = true;
  for (int i = 1; i < kBlock; ++i) run = run && idx[i] == idx[0] + i;
  return run;
}

/// The general list's forces, block by block.
double add_list_forces(const SpringList& l, double c, const Matrix3X& x, const Matrix3X& v,
                       Matrix3X& f) {
  const ListArrays p{x.row(0).data(),    x.row(1).data(),
                     x.row(2).data(),    v.row(0).data(),
                     v.row(1).data(),    v.row(2).data(),
                     f.row(0).data(),    f.row(1).data(),
                     f.row(2).data(),    l.a.data(),
                     l.b.data(),         l.rest.data(),
                     l.stiffness.data(), c};
  const int n = l.size(), full = n - n % kBlock;
  const std::integral_constant<int, kBlock> block;
  alignas(64) double power[kBlock] = {};
  for (int s0 = 0; s0 < full; s0 += kBlock) {
    // the kernel for the block's kind: runs of first ends, of second ends, of both, of neither
    const bool run_a = is_run(p.A + s0), run_b = is_run(p.B + s0);
    if (run_a && run_b)
      list_force_block<true, true>(p, s0, block, power);
    else if (run_a)
      list_force_block<true, false>(p, s0, block, power);
    else if (run_b)
      list_force_block<false, true>(p, s0, block, power);
    else
      list_force_block<false, false>(p, s0, block, power);
  }
  if (full < n) list_force_block<false, false>(p, full, n - full, power);
  double total = 0.0;
  for (double lane : power) total += lane;
  return total;
}

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
  if (!springs.list.empty()) power += add_list_forces(springs.list, c, x, v, f);
  add_bending_forces(springs.bending, x, f);
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
  const SpringList& l = springs.list;
  for (size_t i = 0; i < l.a.size(); ++i) {
    const Vector3 d = x.col(l.b[i]) - x.col(l.a[i]);
    const double vr = (v.col(l.b[i]) - v.col(l.a[i])).dot(d) / (d.norm() + kTinyLength);
    power += c * vr * vr;
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
  const SpringList& l = springs.list;
  for (size_t i = 0; i < l.a.size(); ++i) {
    const double stretch = (x.col(l.b[i]) - x.col(l.a[i])).norm() - l.rest[i];
    e += 0.5 * l.stiffness[i] * stretch * stretch;
  }
  return e + bending_energy(springs.bending, x);
}

StrainStats strain_stats(const SpringSet& springs, const Matrix3X& x) {
  StrainStats s;
  double sum = 0.0;
  bool nan = false;
  // signed strain l / l0 - 1 of each spring; stretch and compression over non-bend springs
  for_each_spring(springs, [&](int p, int q, size_t g, int slot) {
    const double e = (x.col(q) - x.col(p)).norm() / springs.rest(g, slot) - 1.0;
    nan = nan || !std::isfinite(e);
    s.max_abs = std::max(s.max_abs, std::abs(e));
    sum += std::abs(e);
    if (springs.kind(g, slot) == SpringKind::bend) return;
    s.max_stretch = std::max(s.max_stretch, e);
    s.max_compression = std::max(s.max_compression, -e);
  });
  if (nan) {
    const double q = std::numeric_limits<double>::quiet_NaN();
    return {q, q, q, q};
  }
  const int count = springs.count();
  s.mean_abs = count > 0 ? sum / count : 0.0;
  return s;
}

}  // namespace cloth

namespace cloth {

namespace {

/// True when every coordinate is finite and every spring checked has lo l0^2 <= |d|^2 <= hi
/// l0^2 (squared lengths only; written so that a NaN fails); bend springs skipped when
/// skip_bend.
bool within_lengths(const SpringSet& springs, const Matrix3X& x, double lo, double hi,
                    bool skip_bend) {
  const double* __restrict X = x.row(0).data();
  const double* __restrict Y = x.row(1).data();
  const double* __restrict Z = x.row(2).data();
  int bad = 0;
  for (const SpringFamily& fam : springs.families) {
    if (skip_bend && fam.kind == SpringKind::bend) continue;
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
  const SpringList& l = springs.list;
  const int* __restrict A = l.a.data();
  const int* __restrict B = l.b.data();
  const double* __restrict rest = l.rest.data();
  const SpringKind* __restrict kind = l.kind.data();
#pragma omp simd reduction(+ : bad)
  for (int i = 0; i < l.size(); ++i) {
    const int a = A[i], b = B[i];
    const double dx = X[b] - X[a], dy = Y[b] - Y[a], dz = Z[b] - Z[a];
    const double d2 = dx * dx + dy * dy + dz * dz;
    const double r2 = rest[i] * rest[i];
    const bool ok = (d2 <= hi * r2) && (d2 >= lo * r2);
    bad += (!ok && !(skip_bend && kind[i] == SpringKind::bend)) ? 1 : 0;
  }
  // a single particle without springs is checked for finiteness directly
  return bad == 0 && x.allFinite();
}

}  // namespace

bool within_strain(const SpringSet& springs, const Matrix3X& x, double limit) {
  // |d| / l0 - 1 in [-limit, limit]  <=>  (1 - limit)^2 l0^2 <= |d|^2 <= (1 + limit)^2 l0^2
  const double lo = limit < 1.0 ? (1.0 - limit) * (1.0 - limit) : 0.0;
  return within_lengths(springs, x, lo, (1.0 + limit) * (1.0 + limit), false);
}

bool within_stretch(const SpringSet& springs, const Matrix3X& x, double limit) {
  // |d| / l0 - 1 <= limit  <=>  |d|^2 <= (1 + limit)^2 l0^2, bend springs left out
  return within_lengths(springs, x, 0.0, (1.0 + limit) * (1.0 + limit), true);
}

}  // namespace cloth
