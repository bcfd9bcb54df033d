#pragma once
/// @file elastica.hpp
/// The heavy inextensible elastica, solved here for the tests alone (not code under test).
///
/// A strip of bending rigidity B and weight w per unit area and width, clamped horizontally at
/// arc length s = 0 and free at s = L, with theta(s) its angle below the horizontal: the
/// moment of the weight beyond s is B theta'(s) = w int_s^L (x(r) - x(s)) dr, so
///   theta'' = -(w / B) (L - s) cos(theta),   theta(0) = 0,   theta'(L) = 0.
/// In units of the bending length c = (B / w)^(1/3) the shape depends on L / c alone. The
/// boundary-value problem is solved by shooting on theta'(0) = kappa0, which lies in
/// [0, (L/c)^2 / 2] (the moment at the root is at most w L^2 / 2), by bisection, each shot an
/// RK4 integration of (theta, theta', x, y).

#include <cmath>

namespace clothbench::test {

/// Tip of the elastica, in units of c.
struct ElasticaTip {
  double drop = 0;  // vertical fall of the tip below the clamp
  double run = 0;   // horizontal distance of the tip from the clamp
};

/// Integrates from the clamp with theta'(0) = k0 over lambda = L / c; returns theta'(L) and
/// the tip.
inline double shoot(double lambda, double k0, ElasticaTip& tip, int steps = 2000) {
  const double h = lambda / steps;
  double th = 0.0, dth = k0, x = 0.0, y = 0.0;
  auto rhs = [&](double s, double a, double da, double out[4]) {
    out[0] = da;
    out[1] = -(lambda - s) * std::cos(a);
    out[2] = std::cos(a);
    out[3] = std::sin(a);
  };
  for (int i = 0; i < steps; ++i) {
    const double s = i * h;
    double k1[4], k2[4], k3[4], k4[4];
    rhs(s, th, dth, k1);
    rhs(s + h / 2, th + h / 2 * k1[0], dth + h / 2 * k1[1], k2);
    rhs(s + h / 2, th + h / 2 * k2[0], dth + h / 2 * k2[1], k3);
    rhs(s + h, th + h * k3[0], dth + h * k3[1], k4);
    th += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]);
    dth += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]);
    x += h / 6 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2]);
    y += h / 6 * (k1[3] + 2 * k2[3] + 2 * k3[3] + k4[3]);
  }
  tip = {y, x};
  return dth;
}

/// The tip of a strip of overhang lambda = L / c (units of c).
inline ElasticaTip elastica_tip(double lambda) {
  double lo = 0.0, hi = 0.5 * lambda * lambda;
  ElasticaTip tip;
  for (int it = 0; it < 50; ++it) {
    const double mid = 0.5 * (lo + hi);
    (shoot(lambda, mid, tip) < 0 ? lo : hi) = mid;
  }
  shoot(lambda, 0.5 * (lo + hi), tip);
  return tip;
}

/// The bending length c (m) of a strip of overhang l (m) whose tip falls by drop (m): the
/// drop over the overhang grows with l / c, so bisection on it.
inline double bending_length_from_drop(double l, double drop) {
  double lo = 0.05, hi = 5.0;  // l / c: beyond 5 the shooting above finds other roots
  for (int it = 0; it < 50; ++it) {
    const double mid = 0.5 * (lo + hi);
    (elastica_tip(mid).drop / mid < drop / l ? lo : hi) = mid;
  }
  return l / (0.5 * (lo + hi));
}

}  // namespace clothbench::test
