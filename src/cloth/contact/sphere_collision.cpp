#include "cloth/contact/sphere_collision.hpp"

#include <algorithm>
#include <cmath>

namespace cloth {

double resolve_sphere_contacts(const std::vector<Sphere>& spheres, double t, Matrix3X& x,
                               Matrix3X& v, const VectorX& mass, const Matrix3X& free,
                               ContactTally* tally) {
  double removed = 0.0;
  const int n = static_cast<int>(x.cols());
  for (const Sphere& s : spheres) {
    const Vector3 c = s.center_at(t);
    const double shell = s.radius + s.margin;
    const double shell2 = shell * shell;
    const Vector3 vs = s.velocity_at(t);
    for (int p = 0; p < n; ++p) {
      const Vector3 d = x.col(p) - c;
      const double dist2 = d.squaredNorm();
      if (dist2 >= shell2) continue;
      const double dist = std::sqrt(dist2);
      // a particle exactly at the centre is pushed out along +y
      const Vector3 nrm = dist > 0 ? Vector3(d / dist) : Vector3::UnitY();
      const Vector3 target = c + shell * nrm;
      x.col(p) += free.col(p).cwiseProduct(target - x.col(p));
      if (tally) tally->count(p);
      // restitution and friction act on the velocity relative to the sphere
      const Vector3 vold = v.col(p);
      if ((vold - vs).dot(nrm) >= 0) continue;  // not approaching
      v.col(p) += free.col(p).cwiseProduct(contact_velocity(vold, vs, nrm, s).v - vold);
      if (tally) {
        const Vector3 impulse = mass[p] * (v.col(p) - vold);
        tally->impulse += impulse;
        tally->collider_work += impulse.dot(vs);
      }
      removed += 0.5 * mass[p] * (vold.squaredNorm() - v.col(p).squaredNorm());
    }
  }
  return removed;
}

double max_penetration(const std::vector<Sphere>& spheres, double t, const Matrix3X& x) {
  double depth = 0.0;
  for (const Sphere& s : spheres) {
    const Vector3 c = s.center_at(t);
    const double r2 = s.radius * s.radius;
    for (int p = 0; p < x.cols(); ++p) {
      const double dist2 = (x.col(p) - c).squaredNorm();
      if (dist2 < r2) depth = std::max(depth, s.radius - std::sqrt(dist2));
    }
  }
  return depth;
}

}  // namespace cloth
