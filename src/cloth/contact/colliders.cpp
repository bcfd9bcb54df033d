#include "cloth/contact/colliders.hpp"

#include <algorithm>
#include <cmath>

namespace cloth {

Vector3 Motion::displacement(double t) const {
  if (path.empty()) return t * velocity;
  if (t <= path.front()[0]) return Vector3(path.front()[1], path.front()[2], path.front()[3]);
  for (size_t k = 1; k < path.size(); ++k) {
    const auto& a = path[k - 1];
    const auto& b = path[k];
    if (t > b[0]) continue;
    const double s = (t - a[0]) / (b[0] - a[0]);
    return Vector3(a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2]), a[3] + s * (b[3] - a[3]));
  }
  return Vector3(path.back()[1], path.back()[2], path.back()[3]);
}

Vector3 Motion::velocity_at(double t) const {
  if (path.empty()) return velocity;
  for (size_t k = 1; k < path.size(); ++k) {
    const auto& a = path[k - 1];
    const auto& b = path[k];
    if (t >= b[0]) continue;
    return Vector3(b[1] - a[1], b[2] - a[2], b[3] - a[3]) / (b[0] - a[0]);
  }
  return Vector3::Zero();
}

SurfacePoint surface_point(const HalfSpace& s, double t, const Vector3& x) {
  return {(x - s.point - s.displacement(t)).dot(s.normal), s.normal};
}

SurfacePoint surface_point(const Sphere& s, double t, const Vector3& x) {
  const Vector3 d = x - s.center_at(t);
  const double dist = d.norm();
  // a point exactly at the centre is pushed out along +y
  return {dist - s.radius, dist > 0 ? Vector3(d / dist) : Vector3::UnitY()};
}

SurfacePoint surface_point(const Box& s, double t, const Vector3& x) {
  const Vector3 d = x - s.center - s.displacement(t);
  const Vector3 q = d.cwiseAbs() - s.half_extents;
  const Vector3 sign = d.unaryExpr([](double c) { return c < 0 ? -1.0 : 1.0; });
  if (q.maxCoeff() > 0) {
    const Vector3 out = q.cwiseMax(0.0);
    const double dist = out.norm();
    return {dist, Vector3(sign.cwiseProduct(out) / dist)};
  }
  // inside: out through the nearest face
  Eigen::Index axis = 0;
  const double depth = q.maxCoeff(&axis);
  Vector3 n = Vector3::Zero();
  n[axis] = sign[axis];
  return {depth, n};
}

namespace {

// a unit vector normal to u (unit)
Vector3 any_normal(const Vector3& u) {
  const Vector3 helper = std::abs(u.x()) < 0.9 ? Vector3::UnitX() : Vector3::UnitY();
  return (helper - helper.dot(u) * u).normalized();
}

}  // namespace

SurfacePoint surface_point(const Capsule& s, double t, const Vector3& x) {
  const Vector3 a = s.a + s.displacement(t);
  const Vector3 ab = s.b - s.a;
  const double along = std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  const Vector3 d = x - (a + along * ab);
  const double dist = d.norm();
  return {dist - s.radius, dist > 0 ? Vector3(d / dist) : any_normal(ab.normalized())};
}

SurfacePoint surface_point(const Cylinder& s, double t, const Vector3& x) {
  const Vector3 d = x - s.center - s.displacement(t);
  const double rho = std::hypot(d.x(), d.z());
  // radial direction in the x-z plane; +x on the axis
  const Vector3 radial = rho > 0 ? Vector3(d.x() / rho, 0.0, d.z() / rho) : Vector3::UnitX();
  const Vector3 up(0.0, d.y() < 0 ? -1.0 : 1.0, 0.0);
  const double qr = rho - s.radius;
  const double qy = std::abs(d.y()) - 0.5 * s.height;
  if (qr > 0 && qy > 0) {
    const double dist = std::hypot(qr, qy);
    return {dist, Vector3((qr * radial + qy * up) / dist)};
  }
  return qr > qy ? SurfacePoint{qr, radial} : SurfacePoint{qy, up};
}

namespace {

// the response to one shape of every particle within its shell; x0 holds the positions at
// the step's start
template <class Shape>
void resolve_each(const std::vector<Shape>& shapes, double t, double h, const Matrix3X& x0,
                  Matrix3X& x, Matrix3X& v, const Matrix3X& free, const VectorX& mass,
                  ContactTally& tally) {
  const Eigen::Index n = x.cols();
  for (const Shape& s : shapes) {
    const Vector3 vs = s.velocity_at(t - h);  // over the step that ends at t
    const Vector3 moved = s.displacement(t) - s.displacement(t - h);
    for (Eigen::Index p = 0; p < n; ++p) {
      const SurfacePoint sp = surface_point(s, t, Vector3(x.col(p)));
      if (sp.distance > s.margin) continue;
      const Vector3& nrm = sp.normal;
      x.col(p) += free.col(p).cwiseProduct((s.margin - sp.distance) * nrm);
      tally.count(p);
      // restitution and friction act on the velocity relative to the collider
      const Vector3 vold = v.col(p);
      if ((vold - vs).dot(nrm) >= 0) continue;  // not approaching
      const ContactVelocity cv = contact_velocity(vold, vs, nrm, s);
      const double keep = cv.keep;
      v.col(p) += free.col(p).cwiseProduct(cv.v - vold);
      const Vector3 impulse = mass[p] * (v.col(p) - vold);
      tally.impulse += impulse;
      tally.collider_work += impulse.dot(vs);
      // friction shortens the step's travel along the surface alike, so that a sticking
      // particle stays put on the collider
      Vector3 travel = x.col(p) - x0.col(p) - moved;
      travel -= travel.dot(nrm) * nrm;
      x.col(p) += free.col(p).cwiseProduct((keep - 1.0) * travel);
    }
  }
}

template <class Shape>
void deepest(const std::vector<Shape>& shapes, double t, const Matrix3X& x, double& depth) {
  for (const Shape& s : shapes)
    for (Eigen::Index p = 0; p < x.cols(); ++p)
      depth = std::max(depth, -surface_point(s, t, Vector3(x.col(p))).distance);
}

}  // namespace

std::int64_t resolve_shape_contacts(const Shapes& shapes, double t, double h, const Matrix3X& x0,
                                    Matrix3X& x, Matrix3X& v, const Matrix3X& free,
                                    const VectorX& mass, ContactTally& tally) {
  resolve_each(shapes.planes, t, h, x0, x, v, free, mass, tally);
  resolve_each(shapes.boxes, t, h, x0, x, v, free, mass, tally);
  resolve_each(shapes.capsules, t, h, x0, x, v, free, mass, tally);
  resolve_each(shapes.cylinders, t, h, x0, x, v, free, mass, tally);
  return static_cast<std::int64_t>(shapes.count()) * x.cols();
}

double max_penetration(const std::vector<Sphere>& spheres, const Shapes& shapes, double t,
                       const Matrix3X& x) {
  double depth = 0.0;
  deepest(spheres, t, x, depth);
  deepest(shapes.planes, t, x, depth);
  deepest(shapes.boxes, t, x, depth);
  deepest(shapes.capsules, t, x, depth);
  deepest(shapes.cylinders, t, x, depth);
  return depth;
}

}  // namespace cloth
