#include "harness/gate/welch_test.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clothbench {

namespace {

// the continued fraction of I_x(a, b), good for x < (a + 1) / (a + b + 2) (modified Lentz)
double beta_fraction(double a, double b, double x) {
  constexpr double tiny = 1e-300, eps = 1e-15;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::abs(d) < tiny) d = tiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= 10000; ++m) {
    // the even and the odd term of step m
    for (int odd = 0; odd < 2; ++odd) {
      const double num = odd ? -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0))
                             : m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m));
      d = 1.0 + num * d;
      if (std::abs(d) < tiny) d = tiny;
      c = 1.0 + num / c;
      if (std::abs(c) < tiny) c = tiny;
      d = 1.0 / d;
      h *= d * c;
      if (odd && std::abs(d * c - 1.0) < eps) return h;
    }
  }
  return h;
}

}  // namespace

double regularized_incomplete_beta(double a, double b, double x) {
  if (!(a > 0) || !(b > 0) || !(x >= 0) || !(x <= 1))
    return std::numeric_limits<double>::quiet_NaN();
  if (x == 0 || x == 1) return x;
  // the prefactor x^a (1 - x)^b / (a B(a, b)), in logarithms
  const double ln_front =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  // the fraction converges fast on the side of the mean; the other side by symmetry
  if (x < (a + 1.0) / (a + b + 2.0)) return std::exp(ln_front) * beta_fraction(a, b, x) / a;
  return 1.0 - std::exp(ln_front) * beta_fraction(b, a, 1.0 - x) / b;
}

void sample_moments(const std::vector<double>& v, double& mean, double& sd) {
  mean = 0;
  for (double x : v) mean += x;
  mean /= double(v.size());
  double ss = 0;
  for (double x : v) ss += (x - mean) * (x - mean);
  sd = std::sqrt(ss / double(v.size() - 1));
}

double student_t_two_sided(double t, double dof) {
  if (std::isnan(t) || !(dof > 0)) return std::numeric_limits<double>::quiet_NaN();
  if (std::isinf(t)) return 0.0;
  return regularized_incomplete_beta(0.5 * dof, 0.5, dof / (dof + t * t));
}

WelchResult welch_test(const std::vector<double>& a, const std::vector<double>& b) {
  WelchResult r;
  const auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (a.size() < 2 || b.size() < 2 || !finite(a) || !finite(b)) {
    r.t = r.dof = r.p = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  sample_moments(a, r.mean_a, r.sd_a);
  sample_moments(b, r.mean_b, r.sd_b);
  const double va = r.sd_a * r.sd_a / double(a.size()), vb = r.sd_b * r.sd_b / double(b.size());
  const double diff = r.mean_b - r.mean_a;
  // no spread on either side: the means are equal or they are not
  if (va + vb == 0) {
    r.t = diff == 0 ? 0.0 : std::copysign(INFINITY, diff);
    r.dof = double(a.size() + b.size() - 2);
    r.p = diff == 0 ? 1.0 : 0.0;
    return r;
  }
  r.t = diff / std::sqrt(va + vb);
  r.dof = (va + vb) * (va + vb) / (va * va / double(a.size() - 1) + vb * vb / double(b.size() - 1));
  r.p = student_t_two_sided(r.t, r.dof);
  return r;
}

}  // namespace clothbench
