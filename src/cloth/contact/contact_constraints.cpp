#include "cloth/contact/contact_constraints.hpp"

#include <algorithm>

#include "cloth/contact/colliders.hpp"

namespace cloth {

namespace {

/// Within this of the shell a particle counts as on it (m): the contact pass after a step puts
/// particles on the shell to round-off.
constexpr double kOnShell = 1e-9;
/// Faster than this along the normal a particle on the shell is leaving it (m/s); a held
/// contact ends the step at its fixed normal velocity to round-off.
constexpr double kLeaving = 1e-9;

/// Adds p's constraint against collider c if p touches it or heads into it; true if added.
template <class Shape>
bool try_collider(const Shape& c, int p, double t_end, double h, const Vector3& x0,
                  const Vector3& v0, bool released, std::vector<ContactConstraint>& out) {
  if (c.restitution != 0.0 || c.friction != 0.0) return false;
  // against the collider where it ends the step; leaving means relative to its motion
  const SurfacePoint end = surface_point(c, t_end, x0);
  const double start_depth = surface_point(c, t_end - h, x0).distance;
  const bool touching = end.distance <= c.margin + kOnShell && !released &&
                        end.normal.dot(v0 - c.velocity_at(t_end - h)) <= kLeaving;
  if (!touching && surface_point(c, t_end, x0 + h * v0).distance >= c.margin) return false;
  // land on the shell from above it; a particle already in it keeps its depth (the contact
  // pass lifts it out without giving it a velocity)
  const double nv = (std::min(c.margin, start_depth) - end.distance) / h;
  out.push_back({p, end.normal, nv, (c.displacement(t_end) - c.displacement(t_end - h)) / h});
  return true;
}

}  // namespace

void find_contact_constraints(const Model& m, double t_end, double h, const Matrix3X& x0,
                              const Matrix3X& v0, const std::vector<char>& released,
                              std::vector<ContactConstraint>& out) {
  out.clear();
  for (Eigen::Index p = 0; p < x0.cols(); ++p) {
    // a particle with a held axis (or on a handle) keeps the contact pass after the step
    if (m.free.col(p).minCoeff() == 0.0) continue;
    const bool rel = !released.empty() && released[p] != 0;
    const Vector3 x = x0.col(p), v = v0.col(p);
    const int i = static_cast<int>(p);
    auto any_of = [&](const auto& colliders) {
      return std::any_of(colliders.begin(), colliders.end(), [&](const auto& c) {
        return try_collider(c, i, t_end, h, x, v, rel, out);
      });
    };
    any_of(m.spheres) || any_of(m.shapes.planes) || any_of(m.shapes.boxes) ||
        any_of(m.shapes.capsules) || any_of(m.shapes.cylinders);
  }
}

void remove_normal_parts(const std::vector<ContactConstraint>& contacts, Matrix3X& u) {
  for (const ContactConstraint& c : contacts)
    u.col(c.particle) -= c.normal.dot(u.col(c.particle)) * c.normal;
}

}  // namespace cloth
