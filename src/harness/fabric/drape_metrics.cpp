#include "harness/fabric/drape_metrics.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include "cloth/model/constants.hpp"

namespace clothbench {

namespace {

using cloth::kPi;

/// An orthonormal basis (e1, e2) of the plane normal to gravity.
void horizontal_basis(const cloth::Vector3& gravity, cloth::Vector3* e1, cloth::Vector3* e2) {
  const cloth::Vector3 n = -gravity.normalized();
  const cloth::Vector3 helper =
      std::abs(n.x()) < 0.9 ? cloth::Vector3::UnitX() : cloth::Vector3::UnitZ();
  *e1 = (helper - helper.dot(n) * n).normalized();
  *e2 = n.cross(*e1);
}

/// Fills each empty bin (negative) by linear interpolation between its nearest filled
/// neighbours around the circle; all bins stay empty when none is filled.
void fill_empty_bins(std::vector<double>& r) {
  const int n = static_cast<int>(r.size());
  int first = -1;
  for (int k = 0; k < n && first < 0; ++k)
    if (r[size_t(k)] >= 0) first = k;
  if (first < 0) return;
  // walk the circle from a filled bin, filling each gap between two filled bins
  int last = first;
  for (int step = 1; step <= n; ++step) {
    const int k = (first + step) % n;
    if (r[size_t(k)] < 0) continue;
    const int gap = (k - last + n) % n;
    for (int g = 1; g < gap; ++g)
      r[size_t((last + g) % n)] =
          r[size_t(last)] + (r[size_t(k)] - r[size_t(last)]) * g / double(gap);
    last = k;
  }
}

}  // namespace

DrapeProfile drape_profile(const cloth::Matrix3X& x, const std::vector<cloth::Triangle>& triangles,
                           const cloth::Vector3& axis_point, const cloth::Vector3& gravity) {
  if (!(gravity.norm() > 0))
    throw std::invalid_argument("drape profile: expected a non-zero gravity");
  cloth::Vector3 e1, e2;
  horizontal_basis(gravity, &e1, &e2);
  DrapeProfile p;
  p.radius.assign(kDrapeProfileBins, -1.0);
  const double bin = 2 * kPi / kDrapeProfileBins;
  // points within 5 % of the farthest vertex's radius of the axis are never on the outline
  double reach = 0;
  for (Eigen::Index q = 0; q < x.cols(); ++q)
    reach =
        std::max(reach, std::hypot(e1.dot(x.col(q) - axis_point), e2.dot(x.col(q) - axis_point)));
  // each triangle edge, sampled so that consecutive samples are under half a bin apart in angle
  auto sample = [&](const cloth::Vector3& a, const cloth::Vector3& b) {
    const Eigen::Vector2d pa(e1.dot(a - axis_point), e2.dot(a - axis_point));
    const Eigen::Vector2d pb(e1.dot(b - axis_point), e2.dot(b - axis_point));
    const double near = std::max(std::min(pa.norm(), pb.norm()), std::max(0.05 * reach, 1e-12));
    const int n = 1 + static_cast<int>(std::ceil(2 * (pb - pa).norm() / (near * bin)));
    for (int s = 0; s <= std::min(n, 4096); ++s) {
      const Eigen::Vector2d q = pa + (pb - pa) * (double(s) / std::min(n, 4096));
      const double angle = std::atan2(q.y(), q.x()) + kPi;
      const int k = std::min(kDrapeProfileBins - 1, static_cast<int>(angle / bin));
      p.radius[size_t(k)] = std::max(p.radius[size_t(k)], q.norm());
    }
  };
  for (const cloth::Triangle& t : triangles)
    for (int e = 0; e < 3; ++e) sample(x.col(t[e]), x.col(t[(e + 1) % 3]));
  fill_empty_bins(p.radius);
  return p;
}

std::vector<double> smoothed_profile(const std::vector<double>& radius, double degrees) {
  const int n = static_cast<int>(radius.size());
  const int half = static_cast<int>(std::lround(degrees / 2 * n / 360.0));
  std::vector<double> out(radius.size());
  for (int k = 0; k < n; ++k) {
    double sum = 0;
    for (int j = -half; j <= half; ++j) sum += radius[size_t(((k + j) % n + n) % n)];
    out[size_t(k)] = sum / (2 * half + 1);
  }
  return out;
}

int count_local_maxima(const std::vector<double>& v, double min_prominence) {
  const int n = static_cast<int>(v.size());
  if (n < 3) return 0;
  // walk the circle once from its lowest point: a peak counts when, having risen at least the
  // prominence above the last trough, the sequence falls at least as much below it
  const int start = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
  int peaks = 0;
  bool rising = true;
  double low = v[size_t(start)], high = low;
  for (int s = 1; s <= n; ++s) {
    const double cur = v[size_t((start + s) % n)];
    if (rising) {
      high = std::max(high, cur);
      if (high - cur > min_prominence && high - low > min_prominence) {
        ++peaks;
        rising = false;
        low = cur;
      }
    } else {
      low = std::min(low, cur);
      if (cur - low > min_prominence) {
        rising = true;
        high = cur;
      }
    }
  }
  return peaks;
}

double fold_prominence(const std::vector<double>& smooth) {
  double mean = 0;
  for (double r : smooth) mean += r;
  return kFoldProminence * mean / std::max<size_t>(smooth.size(), 1);
}

int drape_folds(const DrapeProfile& profile) {
  const std::vector<double> smooth = smoothed_profile(profile.radius, kFoldSmoothingDegrees);
  return count_local_maxima(smooth, fold_prominence(smooth));
}

std::vector<TestMetric> drape_rows(const DrapeProfile& profile, double drape_coefficient) {
  const std::vector<double> smooth = smoothed_profile(profile.radius, kFoldSmoothingDegrees);
  const auto [lo, hi] = std::minmax_element(smooth.begin(), smooth.end());
  return {{"drape_coefficient", drape_coefficient, "1"},
          {"folds", double(count_local_maxima(smooth, fold_prominence(smooth))), "1"},
          {"min_radius", *lo, "m"},
          {"max_radius", *hi, "m"}};
}

}  // namespace clothbench
