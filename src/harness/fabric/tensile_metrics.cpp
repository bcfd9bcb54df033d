#include "harness/fabric/tensile_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include "cloth/model/constants.hpp"

namespace clothbench {

namespace {

using cloth::kNaN;

/// The middle of the gap between sorted rest coordinates s nearest to at.
double gap_middle(std::vector<double> s, double at) {
  std::sort(s.begin(), s.end());
  double best = kNaN, distance = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k + 1 < s.size(); ++k) {
    // a gap narrower than round-off is one particle column
    if (!(s[k + 1] - s[k] > 1e-9 * (s.back() - s.front()))) continue;
    const double mid = 0.5 * (s[k] + s[k + 1]);
    if (std::abs(mid - at) < distance) {
      distance = std::abs(mid - at);
      best = mid;
    }
  }
  return best;
}

}  // namespace

TensileSetup tensile_setup(const cloth::Matrix3X& x0, const std::vector<std::uint8_t>& held,
                           const std::vector<int>& handle_particles, const cloth::Vector3& axis,
                           double width) {
  TensileSetup s;
  s.axis = axis.normalized();
  s.width = width;
  // the clamp's last particle and the handle's first, along the axis
  double clamp = -std::numeric_limits<double>::infinity();
  double handle = std::numeric_limits<double>::infinity();
  for (Eigen::Index p = 0; p < x0.cols(); ++p)
    if (size_t(p) < held.size() && held[size_t(p)] == cloth::kHoldAll)
      clamp = std::max(clamp, x0.col(p).dot(s.axis));
  for (int p : handle_particles) handle = std::min(handle, x0.col(p).dot(s.axis));
  if (!std::isfinite(clamp) || !std::isfinite(handle) || !(handle > clamp))
    throw std::invalid_argument(
        "strip-tensile: expected particles held on all axes (the clamp) before the handle's "
        "particles along the extension axis");
  s.clamp = clamp;
  s.gauge = handle - clamp;
  // the section: between the two particle columns nearest the gauge's middle
  std::vector<double> along(size_t(x0.cols()));
  for (Eigen::Index p = 0; p < x0.cols(); ++p) along[size_t(p)] = x0.col(p).dot(s.axis);
  s.section = gap_middle(along, clamp + 0.5 * s.gauge);
  return s;
}

double section_force_per_width(const cloth::SpringSet& springs, const cloth::Matrix3X& x0,
                               const cloth::Matrix3X& x, const TensileSetup& setup) {
  double sum = 0;
  for (const cloth::SpringLink& l : springs.links()) {
    const double a = x0.col(l.a).dot(setup.axis) - setup.section;
    const double b = x0.col(l.b).dot(setup.axis) - setup.section;
    if (!(a * b < 0)) continue;
    // oriented from the clamp's side to the handle's: tension pulls the far end back
    const cloth::Vector3 d =
        a < 0 ? cloth::Vector3(x.col(l.b) - x.col(l.a)) : cloth::Vector3(x.col(l.a) - x.col(l.b));
    const double length = d.norm();
    sum += l.stiffness * (length - l.rest) * d.dot(setup.axis) / length;
  }
  return sum / setup.width;
}

std::vector<TensilePoint> tensile_curve(const cloth::SpringSet& springs, const cloth::Matrix3X& x0,
                                        const TensileSetup& setup, const cloth::Motion& handle,
                                        const std::vector<double>& t,
                                        const std::vector<cloth::Matrix3X>& x) {
  std::vector<TensilePoint> curve;
  for (size_t k = 0; k < std::min(t.size(), x.size()); ++k) {
    TensilePoint p;
    p.t = t[k];
    p.strain = handle.displacement(t[k]).dot(setup.axis) / setup.gauge;
    p.force_per_width = section_force_per_width(springs, x0, x[k], setup);
    curve.push_back(p);
  }
  return curve;
}

double tensile_slope(const std::vector<TensilePoint>& curve, double fit_strain) {
  // least squares with an intercept, about the means (no cancellation)
  double n = 0, se = 0, sf = 0;
  for (const TensilePoint& p : curve)
    if (p.strain > 0 && p.strain <= fit_strain) {
      n += 1;
      se += p.strain;
      sf += p.force_per_width;
    }
  if (n < 3) return kNaN;
  const double me = se / n, mf = sf / n;
  double sxy = 0, sxx = 0;
  for (const TensilePoint& p : curve)
    if (p.strain > 0 && p.strain <= fit_strain) {
      sxy += (p.strain - me) * (p.force_per_width - mf);
      sxx += (p.strain - me) * (p.strain - me);
    }
  return sxx > 0 ? sxy / sxx : kNaN;
}

std::vector<TestMetric> tensile_rows(const std::vector<TensilePoint>& curve, double fit_strain) {
  double max_strain = kNaN, max_force = kNaN;
  for (const TensilePoint& p : curve) {
    if (!(p.strain <= max_strain)) max_strain = p.strain;
    if (!(p.force_per_width <= max_force)) max_force = p.force_per_width;
  }
  return {{"tensile_stiffness", tensile_slope(curve, fit_strain), "N/m"},
          {"fit_strain", fit_strain, "1"},
          {"max_strain", max_strain, "1"},
          {"max_force_per_width", max_force, "N/m"}};
}

}  // namespace clothbench
