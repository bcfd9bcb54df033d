#include "cloth/analysis/element_distance.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace cloth {
namespace {

/// Squared distance from p to the segment [a, b]: the clamped projection, and the endpoints
/// too, so rounding in the parameter never makes the answer worse than they are.
double point_segment_squared(const Vector3& p, const Vector3& a, const Vector3& b) {
  const Vector3 ab = b - a;
  const double len2 = ab.squaredNorm();
  // the closest parameter, clamped to the segment (a collapsed segment is its point a)
  double t = len2 > 0 ? (p - a).dot(ab) / len2 : 0.0;
  t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
  return std::min({(p - (a + t * ab)).squaredNorm(), (p - a).squaredNorm(), (p - b).squaredNorm()});
}

}  // namespace

double point_segment_distance(const Vector3& p, const Vector3& a, const Vector3& b) {
  return std::sqrt(point_segment_squared(p, a, b));
}

double point_triangle_distance(const Vector3& p, const Vector3& a, const Vector3& b,
                               const Vector3& c) {
  // the boundary: three point-segment distances
  double best = std::min({point_segment_squared(p, a, b), point_segment_squared(p, b, c),
                          point_segment_squared(p, c, a)});
  // the interior: the projection onto the plane, when it falls inside the triangle
  const Vector3 n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0 && std::isfinite(n2)) {
    const bool inside = (b - a).cross(p - a).dot(n) >= 0 && (c - b).cross(p - b).dot(n) >= 0 &&
                        (a - c).cross(p - c).dot(n) >= 0;
    if (inside) {
      const double h = n.dot(p - a);
      const double plane = h * h / n2;
      if (plane < best) best = plane;
    }
  }
  return std::sqrt(best);
}

double segment_segment_distance(const Vector3& p0, const Vector3& p1, const Vector3& q0,
                                const Vector3& q1) {
  // the boundary of the parameter square: four point-segment distances
  double best = std::min({point_segment_squared(p0, q0, q1), point_segment_squared(p1, q0, q1),
                          point_segment_squared(q0, p0, p1), point_segment_squared(q1, p0, p1)});
  // the interior: the common perpendicular, when both feet fall inside the segments
  const Vector3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), b = d1.dot(d2);
  const double c = d1.dot(r), f = d2.dot(r);
  const double denom = a * e - b * b;
  if (denom > 0 && std::isfinite(denom)) {
    const double s = (b * f - c * e) / denom;
    const double t = (a * f - b * c) / denom;
    if (s > 0 && s < 1 && t > 0 && t < 1) {
      const double inner = ((p0 + s * d1) - (q0 + t * d2)).squaredNorm();
      if (inner < best) best = inner;
    }
  }
  return std::sqrt(best);
}

}  // namespace cloth
