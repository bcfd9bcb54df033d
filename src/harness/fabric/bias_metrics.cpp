#include "harness/fabric/bias_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <Eigen/Dense>

#include "cloth/model/constants.hpp"
#include "harness/fabric/tensile_metrics.hpp"

namespace clothbench {

namespace {

using cloth::kNaN;
using cloth::kPi;
constexpr double kDegree = kPi / 180.0;

/// The extent of the rest coordinates along dir: its lowest and highest.
std::pair<double, double> extent(const cloth::Matrix3X& x0, const cloth::Vector3& dir) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (Eigen::Index p = 0; p < x0.cols(); ++p) {
    lo = std::min(lo, x0.col(p).dot(dir));
    hi = std::max(hi, x0.col(p).dot(dir));
  }
  return {lo, hi};
}

/// F_s at half_angle, linear between the known (angle, F_s) pairs sorted by angle, from
/// (0, 0); 0 at or below 0; NaN beyond the last pair (nothing known there yet).
double shear_force_at(const std::vector<std::pair<double, double>>& known, double half_angle) {
  if (!(half_angle > 0)) return 0.0;
  double a0 = 0.0, f0 = 0.0;
  for (const auto& [a1, f1] : known) {
    if (!(a1 > 0)) continue;
    if (a1 >= half_angle) return a1 > a0 ? f0 + (f1 - f0) * (half_angle - a0) / (a1 - a0) : f1;
    a0 = a1, f0 = f1;
  }
  return kNaN;
}

}  // namespace

BiasSetup bias_setup(const cloth::Matrix3X& x0, const std::vector<std::uint8_t>& held,
                     const std::vector<int>& handle_particles, const cloth::Vector3& axis,
                     const cloth::Vector3& across) {
  // the clamp's last particle and the handle's first, and the section between, as a strip's
  const auto [low, high] = extent(x0, across.normalized());
  const TensileSetup t = tensile_setup(x0, held, handle_particles, axis, high - low);
  BiasSetup s;
  s.axis = t.axis;
  s.across = across.normalized();
  s.length = t.gauge;
  s.width = high - low;
  s.section = t.section;
  // the central zone: a square of side W/2 about the middle of the gauge and of the width
  const double mid_along = t.clamp + 0.5 * t.gauge, mid_across = 0.5 * (low + high);
  for (Eigen::Index p = 0; p < x0.cols(); ++p)
    if (std::abs(x0.col(p).dot(s.axis) - mid_along) <= 0.25 * s.width * (1 + 1e-12) &&
        std::abs(x0.col(p).dot(s.across) - mid_across) <= 0.25 * s.width * (1 + 1e-12))
      s.central.push_back(int(p));
  if (s.central.size() < 3)
    throw std::invalid_argument(
        "bias-extension: expected at least 3 particles within a quarter of the width of the "
        "specimen's centre (the central zone), got " +
        std::to_string(s.central.size()));
  return s;
}

double pin_jointed_angle(double length, double width, double d) {
  if (!(length > width)) return kNaN;
  const double c = (length - width + d) / (std::sqrt(2.0) * (length - width));
  if (!(c >= -1 && c <= 1)) return kNaN;
  return kPi / 2 - 2 * std::acos(c);
}

double central_shear_angle(const cloth::Matrix3X& x0, const cloth::Matrix3X& x,
                           const BiasSetup& setup) {
  // rest coordinates (along, across) and positions about the zone's means
  const int n = int(setup.central.size());
  Eigen::Matrix2Xd r(2, n);
  cloth::Matrix3X y(3, n);
  for (int k = 0; k < n; ++k) {
    const int p = setup.central[size_t(k)];
    r.col(k) << x0.col(p).dot(setup.axis), x0.col(p).dot(setup.across);
    y.col(k) = x.col(p);
  }
  r.colwise() -= r.rowwise().mean();
  y.colwise() -= y.rowwise().mean();
  // the affine map's linear part, F = (y r^T) (r r^T)^-1
  const Eigen::Matrix2d rr = r * r.transpose();
  if (!(std::abs(rr.determinant()) > 1e-12 * rr.squaredNorm())) return kNaN;
  const Eigen::Matrix<double, 3, 2> f = (y * r.transpose()) * rr.inverse();
  // the deformed yarns and the angle between them
  const cloth::Vector3 a = f * Eigen::Vector2d(1, 1), b = f * Eigen::Vector2d(1, -1);
  return kPi / 2 - std::atan2(a.cross(b).norm(), a.dot(b));
}

double bias_section_force(const cloth::SpringSet& springs, const cloth::Matrix3X& x0,
                          const cloth::Matrix3X& x, const BiasSetup& setup) {
  // the strip-tensile's section sum, per a width of 1: the whole force
  TensileSetup t;
  t.axis = setup.axis;
  t.width = 1.0;
  t.section = setup.section;
  return section_force_per_width(springs, x0, x, t);
}

std::vector<double> normalise_shear_force(const std::vector<double>& angle,
                                          const std::vector<double>& force, double length,
                                          double width) {
  const double h = length, w = width;
  std::vector<std::pair<double, double>> known;  // (angle, F_s), sorted by angle
  std::vector<double> out;
  for (size_t k = 0; k < std::min(angle.size(), force.size()); ++k) {
    const double g = angle[k];
    const double half = shear_force_at(known, 0.5 * g);
    const double work = (h / w - 1) * force[k] * (std::cos(g / 2) - std::sin(g / 2));
    // half the angle not reached yet (the first frames): F_s(g/2) taken as F_s(g) / 2
    const double fs = std::isnan(half)
                          ? work / ((2 * h - 3 * w) * std::cos(g) + 0.5 * w * std::cos(g / 2))
                          : (work - w * half * std::cos(g / 2)) / ((2 * h - 3 * w) * std::cos(g));
    out.push_back(fs);
    if (!std::isfinite(fs)) continue;
    const auto at =
        std::upper_bound(known.begin(), known.end(), g,
                         [](double a, const std::pair<double, double>& p) { return a < p.first; });
    known.insert(at, {g, fs});
  }
  return out;
}

std::vector<BiasPoint> bias_curve(const cloth::SpringSet& springs, const cloth::Matrix3X& x0,
                                  const BiasSetup& setup, const cloth::Motion& handle,
                                  const std::vector<double>& t,
                                  const std::vector<cloth::Matrix3X>& x) {
  std::vector<BiasPoint> curve;
  for (size_t k = 0; k < std::min(t.size(), x.size()); ++k) {
    BiasPoint p;
    p.t = t[k];
    p.displacement = handle.displacement(t[k]).dot(setup.axis);
    p.force = bias_section_force(springs, x0, x[k], setup);
    p.angle_pin = pin_jointed_angle(setup.length, setup.width, p.displacement);
    p.angle = central_shear_angle(x0, x[k], setup);
    curve.push_back(p);
  }
  // the shear force at either angle
  std::vector<double> measured, pin, force;
  for (const BiasPoint& p : curve) {
    measured.push_back(p.angle);
    pin.push_back(p.angle_pin);
    force.push_back(p.force);
  }
  const std::vector<double> fs = normalise_shear_force(measured, force, setup.length, setup.width);
  const std::vector<double> fp = normalise_shear_force(pin, force, setup.length, setup.width);
  for (size_t k = 0; k < curve.size(); ++k) {
    curve[k].shear_force = fs[k];
    curve[k].shear_force_pin = fp[k];
  }
  return curve;
}

double shear_slope(const std::vector<BiasPoint>& curve, double fit_angle, bool pin_jointed) {
  // the points in the range, then least squares with an intercept about the means
  const double top = fit_angle * kDegree;
  std::vector<double> a, f;
  for (const BiasPoint& p : curve) {
    const double angle = pin_jointed ? p.angle_pin : p.angle;
    const double force = pin_jointed ? p.shear_force_pin : p.shear_force;
    if (angle > 0 && angle <= top && std::isfinite(force)) a.push_back(angle), f.push_back(force);
  }
  if (a.size() < 3) return kNaN;
  const double n = double(a.size());
  double ma = 0, mf = 0;
  for (size_t k = 0; k < a.size(); ++k) ma += a[k] / n, mf += f[k] / n;
  double sxy = 0, sxx = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    sxy += (a[k] - ma) * (f[k] - mf);
    sxx += (a[k] - ma) * (a[k] - ma);
  }
  return sxx > 0 ? sxy / sxx : kNaN;
}

std::vector<TestMetric> bias_rows(const std::vector<BiasPoint>& curve, double fit_angle) {
  double max_force = kNaN;
  for (const BiasPoint& p : curve)
    if (!(p.force <= max_force)) max_force = p.force;
  const double last = curve.empty() ? kNaN : curve.back().angle / kDegree;
  const double last_pin = curve.empty() ? kNaN : curve.back().angle_pin / kDegree;
  return {{"shear_stiffness", shear_slope(curve, fit_angle), "N/m/rad"},
          {"shear_stiffness_pin_jointed", shear_slope(curve, fit_angle, true), "N/m/rad"},
          {"fit_angle", fit_angle, "deg"},
          {"final_shear_angle", last, "deg"},
          {"final_shear_angle_pin_jointed", last_pin, "deg"},
          {"max_force", max_force, "N"}};
}

}  // namespace clothbench
