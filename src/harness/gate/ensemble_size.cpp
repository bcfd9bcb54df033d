#include "harness/gate/ensemble_size.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cloth/model/constants.hpp"
#include "harness/gate/welch_test.hpp"

namespace clothbench {

namespace {

using cloth::kNaN;
using cloth::kPi;

/// t with P(|T| >= t) = alpha for Student's t with dof degrees of freedom, by bisection.
double two_sided_critical(double alpha, double dof) {
  double lo = 0, hi = 1;
  while (student_t_two_sided(hi, dof) > alpha) hi *= 2;
  for (int k = 0; k < 200 && hi - lo > 1e-12 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (student_t_two_sided(mid, dof) > alpha ? lo : hi) = mid;
  }
  return hi;
}

double normal_upper(double z) {
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

/// Simpson weight of node k of 0..n (n even).
double simpson(int k, int n) {
  return (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
}

/// Welch's critical values over the split of the spread: nodes theta in [0, pi / 2] with
/// r = sin^2 theta, the Beta(a, a) density in theta times Simpson's weight, and the critical t
/// at the degrees of freedom (N - 1) / (r^2 + (1 - r)^2) of that split.
struct SplitNodes {
  std::vector<double> weight, critical;
};

SplitNodes split_nodes(int n, double alpha) {
  const int m = 256;  // even
  const double a = 0.5 * (n - 1), h = 0.5 * kPi / m;
  // Beta(a, a) in theta: 2 (sin cos)^(2a - 1) / B(a, a)
  const double ln_norm = std::log(2.0) - (2.0 * std::lgamma(a) - std::lgamma(2.0 * a));
  SplitNodes s;
  for (int k = 0; k <= m; ++k) {
    // the density is symmetric about pi / 4: the second half reuses the first half's nodes
    if (k > m / 2) {
      s.weight.push_back(s.weight[size_t(m - k)]);
      s.critical.push_back(s.critical[size_t(m - k)]);
      continue;
    }
    const double th = k * h, sc = std::sin(th) * std::cos(th);
    const double r = std::sin(th) * std::sin(th);
    const double density = sc > 0 ? std::exp(ln_norm + (2.0 * a - 1.0) * std::log(sc))
                                  : (2.0 * a - 1.0 == 0 ? std::exp(ln_norm) : 0.0);
    s.weight.push_back(simpson(k, m) * h / 3.0 * density);
    // a node of no weight needs no critical value
    s.critical.push_back(
        s.weight.back() > 1e-14
            ? two_sided_critical(alpha, double(n - 1) / (r * r + (1.0 - r) * (1.0 - r)))
            : NAN);
  }
  return s;
}

/// P(|Z + lambda| > c sqrt(W / dof)) with W chi-square(dof): over s = sqrt(W / dof) by
/// Simpson's rule.
double two_tails(double lambda, double dof, double c) {
  // density of s: 2 dof s f_chi2(dof s^2), in logarithms
  const double ln_norm = std::log(2.0 * dof) - 0.5 * dof * std::log(2.0) - std::lgamma(0.5 * dof);
  // s has mean near 1 and spread about 1 / sqrt(2 dof): outside [s_min, s_max] lies less than
  // 1e-12 of it (for dof = 2, s^2 is exponential with mean 1)
  const double spread = 1.0 / std::sqrt(2.0 * dof);
  const double s_min = std::max(0.0, 1.0 - 10.0 * spread);
  const double s_max = 1.0 + 10.0 * spread * (1.0 + 2.0 / std::sqrt(dof));
  const int n = 400;  // even
  const double h = (s_max - s_min) / n;
  double sum = 0;
  for (int k = 0; k <= n; ++k) {
    const double s = s_min + k * h, v = dof * s * s;
    if (s <= 0) continue;
    const double density =
        std::exp(ln_norm + std::log(s) + (0.5 * dof - 1.0) * std::log(v) - 0.5 * v);
    sum += simpson(k, n) * density * (normal_upper(c * s - lambda) + normal_upper(c * s + lambda));
  }
  return sum * h / 3.0;
}

double power_at(double lambda, int n, const SplitNodes& split) {
  double p = 0;
  for (size_t k = 0; k < split.weight.size(); ++k)
    if (split.weight[k] > 1e-14)
      p += split.weight[k] * two_tails(lambda, 2.0 * (n - 1), split.critical[k]);
  return p;
}

}  // namespace

double welch_power(double shift_over_sd, int n, double alpha) {
  if (n < 2 || !(alpha > 0 && alpha < 1) || std::isnan(shift_over_sd)) return kNaN;
  return power_at(std::abs(shift_over_sd) / std::sqrt(2.0 / n), n, split_nodes(n, alpha));
}

double detectable_shift(double sd, int n, double alpha, double power) {
  if (n < 2 || !(sd >= 0) || !std::isfinite(sd) || !(alpha > 0 && alpha < 1)) return kNaN;
  if (sd == 0) return 0.0;
  const SplitNodes split = split_nodes(n, alpha);
  // the power rises with lambda: bisection
  double lo = 0, hi = 1;
  while (power_at(hi, n, split) < power) hi *= 2;
  for (int k = 0; k < 100 && hi - lo > 1e-7 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (power_at(mid, n, split) < power ? lo : hi) = mid;
  }
  return hi * std::sqrt(2.0 / n) * sd;
}

int members_needed(double sd, double shift, double alpha, int n_min, int n_max, double power) {
  if (n_min < 2) n_min = 2;
  if (!(sd >= 0) || !std::isfinite(sd) || !(shift >= 0) || n_max < n_min) return 0;
  if (sd == 0) return n_min;
  // the power at the goal rises with N (one power per N, not a bisection on the shift):
  // bisection on N
  auto reaches = [&](int n) { return welch_power(shift / sd, n, alpha) >= power; };
  if (!reaches(n_max)) return 0;
  if (reaches(n_min)) return n_min;
  int lo = n_min, hi = n_max;  // lo misses, hi reaches
  while (hi - lo > 1) {
    const int mid = lo + (hi - lo) / 2;
    (reaches(mid) ? hi : lo) = mid;
  }
  return hi;
}

}  // namespace clothbench
