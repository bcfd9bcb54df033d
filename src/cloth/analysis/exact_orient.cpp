#include "cloth/analysis/exact_orient.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace cloth {
namespace {

// ---- stage 1: the floating-point filter ----

/// Relative error bound of the determinant evaluated in doubles, as a multiple of its
/// permanent: Shewchuk (1997) bounds the same evaluation (three differences, then the cofactor
/// expansion) by (7 + 56 eps) eps with eps = 2^-53; 8 eps leaves a margin.
constexpr double kFilterBound = 8.0 * 0x1p-53;

/// True when a difference is zero or far from overflow and underflow, so the filter's error
/// bound (which assumes neither) holds for every product of three of them.
bool in_filter_range(double t) {
  const double m = std::abs(t);
  return m == 0.0 || (m >= 0x1p-300 && m <= 0x1p300);
}

/// +1/-1 when the double evaluation's sign is certain, 0 when it is not.
int filtered_sign(const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d) {
  const Vector3 u = b - a, v = c - a, w = d - a;
  for (int r = 0; r < 3; ++r)
    if (!in_filter_range(u[r]) || !in_filter_range(v[r]) || !in_filter_range(w[r])) return 0;
  const double yz = v.y() * w.z(), zy = v.z() * w.y();
  const double zx = v.z() * w.x(), xz = v.x() * w.z();
  const double xy = v.x() * w.y(), yx = v.y() * w.x();
  const double det = u.x() * (yz - zy) + u.y() * (zx - xz) + u.z() * (xy - yx);
  const double permanent = std::abs(u.x()) * (std::abs(yz) + std::abs(zy)) +
                           std::abs(u.y()) * (std::abs(zx) + std::abs(xz)) +
                           std::abs(u.z()) * (std::abs(xy) + std::abs(yx));
  const double bound = kFilterBound * permanent;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return 0;
}

// ---- stage 2: exact expansion arithmetic ----

/// Largest exponent spread of the nonzero inputs that stage 2 handles: scaled into
/// [2^-240, 2^241), every product of three and its rounding errors stay normal and finite.
constexpr int kExpansionSpread = 480;

/// x + y = s + e exactly (Knuth's two-sum; round to nearest, no overflow).
inline void two_sum(double x, double y, double& s, double& e) {
  s = x + y;
  const double yv = s - x;
  const double xv = s - yv;
  e = (x - xv) + (y - yv);
}

/// x * y = p + e exactly when nothing underflows (the fused multiply-add rounds only once).
inline void two_product(double x, double y, double& p, double& e) {
  p = x * y;
  e = std::fma(x, y, -p);
}

/// A nonoverlapping expansion, smallest part first, zeros left out (Shewchuk's
/// Grow-Expansion with zero elimination): the sum of its parts is exact.
class Expansion {
 public:
  void add(double b) {
    if (b == 0.0) return;
    double q = b;
    int kept = 0;
    for (int i = 0; i < m_size; ++i) {
      double h = 0;
      two_sum(q, m_part[i], q, h);
      if (h != 0.0) m_part[kept++] = h;
    }
    if (q != 0.0) m_part[kept++] = q;
    m_size = kept;
  }
  /// the sign of the exact sum: that of its largest part
  int sign() const {
    if (m_size == 0) return 0;
    return m_part[m_size - 1] > 0 ? 1 : -1;
  }

 private:
  // 24 triple products of 4 parts each: at most 96 parts, plus one while growing
  std::array<double, 100> m_part{};
  int m_size = 0;
};

/// adds sign * x * y * z to e exactly (four parts)
void add_triple(Expansion& e, double sign, double x, double y, double z) {
  double p = 0, pe = 0, hi = 0, hie = 0, lo = 0, loe = 0;
  two_product(x, y, p, pe);
  two_product(p, z, hi, hie);
  two_product(pe, z, lo, loe);
  e.add(sign * loe);
  e.add(sign * lo);
  e.add(sign * hie);
  e.add(sign * hi);
}

/// adds sign * det[p; q; r] (rows) to e exactly
void add_det3(Expansion& e, double sign, const Vector3& p, const Vector3& q, const Vector3& r) {
  add_triple(e, sign, p.x(), q.y(), r.z());
  add_triple(e, -sign, p.x(), q.z(), r.y());
  add_triple(e, -sign, p.y(), q.x(), r.z());
  add_triple(e, sign, p.y(), q.z(), r.x());
  add_triple(e, sign, p.z(), q.x(), r.y());
  add_triple(e, -sign, p.z(), q.y(), r.x());
}

/// x - y = d + e exactly (two-sum with the sign of y flipped, which is exact).
inline void two_diff(double x, double y, double& d, double& e) {
  two_sum(x, -y, d, e);
}

/// adds sign * (x * y - z * w) * u to e exactly (eight parts)
void add_minor_times(Expansion& e, double sign, double x, double y, double z, double w, double u) {
  double p[4];
  two_product(x, y, p[1], p[0]);
  two_product(z, w, p[3], p[2]);
  p[2] = -p[2];
  p[3] = -p[3];
  for (double part : p) {
    double hi = 0, lo = 0;
    two_product(part, u, hi, lo);
    e.add(sign * lo);
    e.add(sign * hi);
  }
}

/// The exact sign when the differences b - a, c - a, d - a are exact in doubles (often the case
/// for nearby points): the 3 by 3 determinant of u, v, w as 24 exact parts instead of 96.
/// Returns 2 when a difference is not exact.
int difference_sign(const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d) {
  Vector3 u, v, w;
  for (int r = 0; r < 3; ++r) {
    double eu = 0, ev = 0, ew = 0;
    two_diff(b[r], a[r], u[r], eu);
    two_diff(c[r], a[r], v[r], ev);
    two_diff(d[r], a[r], w[r], ew);
    if (eu != 0.0 || ev != 0.0 || ew != 0.0) return 2;
  }
  Expansion e;
  add_minor_times(e, 1.0, v.y(), w.z(), v.z(), w.y(), u.x());
  add_minor_times(e, 1.0, v.z(), w.x(), v.x(), w.z(), u.y());
  add_minor_times(e, 1.0, v.x(), w.y(), v.y(), w.x(), u.z());
  return e.sign();
}

/// The exact sign from scaled coordinates (every nonzero magnitude in [2^-240, 2^241)):
/// det[b - a, c - a, d - a] = det[b;c;d] - det[a;c;d] + det[a;b;d] - det[a;b;c], the
/// expansion of the 4 by 4 determinant with rows (p, 1) along its column of ones.
int expansion_sign(const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d) {
  const int from_differences = difference_sign(a, b, c, d);
  if (from_differences != 2) return from_differences;
  Expansion e;
  add_det3(e, 1.0, b, c, d);
  add_det3(e, -1.0, a, c, d);
  add_det3(e, 1.0, a, b, d);
  add_det3(e, -1.0, a, b, c);
  return e.sign();
}

// ---- stage 3: big integers ----

/// A signed integer of any size: magnitude in 32-bit limbs, least significant first.
struct BigInt {
  bool negative = false;
  std::vector<std::uint32_t> mag;  // no leading zero limbs; empty for zero
};

void trim(BigInt& x) {
  while (!x.mag.empty() && x.mag.back() == 0) x.mag.pop_back();
  if (x.mag.empty()) x.negative = false;
}

/// m * 2^shift for a signed integer |m| < 2^63
BigInt shifted(std::int64_t m, int shift) {
  BigInt r;
  r.negative = m < 0;
  std::uint64_t v = m < 0 ? std::uint64_t(-(m + 1)) + 1 : std::uint64_t(m);
  r.mag.assign(static_cast<std::size_t>(shift / 32), 0u);
  const int bits = shift % 32;
  // the low limb takes the bits of v shifted in, the rest carries into the next limbs
  std::uint32_t carry = 0;
  for (int k = 0; k < 2; ++k) {
    const std::uint32_t limb = std::uint32_t(v >> (32 * k));
    const std::uint64_t wide = (std::uint64_t(limb) << bits) | carry;
    r.mag.push_back(std::uint32_t(wide));
    carry = std::uint32_t(wide >> 32);
  }
  r.mag.push_back(carry);
  trim(r);
  return r;
}

int compare_magnitude(const BigInt& x, const BigInt& y) {
  if (x.mag.size() != y.mag.size()) return x.mag.size() < y.mag.size() ? -1 : 1;
  for (std::size_t i = x.mag.size(); i-- > 0;)
    if (x.mag[i] != y.mag[i]) return x.mag[i] < y.mag[i] ? -1 : 1;
  return 0;
}

/// x + y, or x - y when subtract
BigInt add(const BigInt& x, const BigInt& y, bool subtract = false) {
  const bool y_negative = subtract ? !y.negative : y.negative;
  BigInt r;
  if (x.negative == y_negative) {
    // same signs: add the magnitudes
    r.negative = x.negative;
    const std::size_t n = std::max(x.mag.size(), y.mag.size());
    std::uint64_t carry = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t s =
          carry + (i < x.mag.size() ? x.mag[i] : 0u) + (i < y.mag.size() ? y.mag[i] : 0u);
      r.mag.push_back(std::uint32_t(s));
      carry = s >> 32;
    }
    r.mag.push_back(std::uint32_t(carry));
  } else {
    // opposite signs: the larger magnitude minus the smaller, with the larger's sign
    const bool x_larger = compare_magnitude(x, y) >= 0;
    const BigInt& big = x_larger ? x : y;
    const BigInt& small = x_larger ? y : x;
    r.negative = x_larger ? x.negative : y_negative;
    std::int64_t borrow = 0;
    for (std::size_t i = 0; i < big.mag.size(); ++i) {
      std::int64_t s =
          std::int64_t(big.mag[i]) - borrow - (i < small.mag.size() ? small.mag[i] : 0);
      borrow = s < 0 ? 1 : 0;
      r.mag.push_back(std::uint32_t(s + (borrow << 32)));
    }
  }
  trim(r);
  return r;
}

BigInt multiply(const BigInt& x, const BigInt& y) {
  BigInt r;
  if (x.mag.empty() || y.mag.empty()) return r;
  r.negative = x.negative != y.negative;
  r.mag.assign(x.mag.size() + y.mag.size(), 0u);
  for (std::size_t i = 0; i < x.mag.size(); ++i) {
    std::uint64_t carry = 0;
    for (std::size_t j = 0; j < y.mag.size(); ++j) {
      const std::uint64_t t = std::uint64_t(x.mag[i]) * y.mag[j] + r.mag[i + j] + carry;
      r.mag[i + j] = std::uint32_t(t);
      carry = t >> 32;
    }
    r.mag[i + y.mag.size()] = std::uint32_t(carry);
  }
  trim(r);
  return r;
}

}  // namespace

int orient3d_sign_wide(const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d) {
  // every coordinate is m * 2^k with an integer |m| < 2^53: write them over the smallest k
  const std::array<const Vector3*, 4> pts{&a, &b, &c, &d};
  int k_min = 0;
  bool any = false;
  for (const Vector3* p : pts)
    for (int r = 0; r < 3; ++r)
      if ((*p)[r] != 0.0) {
        int e = 0;
        std::frexp((*p)[r], &e);
        k_min = any ? std::min(k_min, e - 53) : e - 53;
        any = true;
      }
  if (!any) return 0;
  std::array<std::array<BigInt, 3>, 4> big;
  for (int i = 0; i < 4; ++i)
    for (int r = 0; r < 3; ++r) {
      int e = 0;
      const double f = std::frexp((*pts[i])[r], &e);
      const auto m = static_cast<std::int64_t>(std::ldexp(f, 53));
      big[i][r] = m == 0 ? BigInt{} : shifted(m, e - 53 - k_min);
    }
  // the determinant of the exact differences
  std::array<std::array<BigInt, 3>, 3> rows;
  for (int i = 0; i < 3; ++i)
    for (int r = 0; r < 3; ++r) rows[i][r] = add(big[i + 1][r], big[0][r], true);
  const auto& u = rows[0];
  const auto& v = rows[1];
  const auto& w = rows[2];
  BigInt det = multiply(u[0], add(multiply(v[1], w[2]), multiply(v[2], w[1]), true));
  det = add(det, multiply(u[1], add(multiply(v[2], w[0]), multiply(v[0], w[2]), true)));
  det = add(det, multiply(u[2], add(multiply(v[0], w[1]), multiply(v[1], w[0]), true)));
  if (det.mag.empty()) return 0;
  return det.negative ? -1 : 1;
}

int orient3d_sign(const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d) {
  // stage 1: most inputs are decided in doubles
  const int fast = filtered_sign(a, b, c, d);
  if (fast != 0) return fast;
  // four points sharing one coordinate (a flat cloth in an axis plane): a zero row, exactly 0
  for (int r = 0; r < 3; ++r)
    if (a[r] == b[r] && a[r] == c[r] && a[r] == d[r]) return 0;
  // the exponent range of the nonzero coordinates
  const std::array<const Vector3*, 4> pts{&a, &b, &c, &d};
  int e_min = 0, e_max = 0;
  bool any = false;
  for (const Vector3* p : pts)
    for (int r = 0; r < 3; ++r)
      if ((*p)[r] != 0.0) {
        const int e = std::ilogb((*p)[r]);
        e_min = any ? std::min(e_min, e) : e;
        e_max = any ? std::max(e_max, e) : e;
        any = true;
      }
  if (!any) return 0;
  // stage 3 when the range is too wide for doubles
  if (e_max - e_min > kExpansionSpread) return orient3d_sign_wide(a, b, c, d);
  // stage 2: scale by a power of two (exact, the sign is unchanged) into [2^-240, 2^241),
  // unless the inputs already lie there
  if (e_min >= -240 && e_max <= 240) return expansion_sign(a, b, c, d);
  const int shift = -(e_max + e_min) / 2;
  std::array<Vector3, 4> s;
  for (int i = 0; i < 4; ++i)
    for (int r = 0; r < 3; ++r) s[i][r] = std::ldexp((*pts[i])[r], shift);
  return expansion_sign(s[0], s[1], s[2], s[3]);
}

}  // namespace cloth
