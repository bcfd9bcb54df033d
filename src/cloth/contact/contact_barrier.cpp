#include "cloth/contact/contact_barrier.hpp"

#include <cmath>
#include <limits>

#include "cloth/contact/colliders.hpp"

namespace cloth {

double barrier(double d, double dhat) {
  if (d <= 0.0) return std::numeric_limits<double>::infinity();
  if (d >= dhat) return 0.0;
  const double g = d - dhat;
  return -g * g * std::log(d / dhat);
}

double barrier_slope(double d, double dhat) {
  if (d >= dhat) return 0.0;
  const double g = d - dhat;
  return -2.0 * g * std::log(d / dhat) - g * g / d;
}

double barrier_curvature(double d, double dhat) {
  if (d >= dhat) return 0.0;
  const double g = d - dhat;
  return -2.0 * std::log(d / dhat) - 4.0 * g / d + g * g / (d * d);
}

double friction_f0(double y, double eps) {
  if (y >= eps) return y;
  return -y * y * y / (3.0 * eps * eps) + y * y / eps + eps / 3.0;
}

double friction_f1(double y, double eps) {
  if (y >= eps) return 1.0;
  return 2.0 * y / eps - y * y / (eps * eps);
}

namespace {

/// Calls visit(p, c, sp) for every covered particle p within collider c's layer at t.
template <class Visit>
void for_each_near(const Model& m, const std::vector<char>& covered, double t, const Matrix3X& x,
                   Visit&& visit) {
  auto each = [&](const auto& colliders) {
    for (const auto& c : colliders)
      for (Eigen::Index p = 0; p < x.cols(); ++p) {
        if (!covered[static_cast<size_t>(p)]) continue;
        const SurfacePoint sp = surface_point(c, t, Vector3(x.col(p)));
        if (sp.distance < c.margin) visit(static_cast<int>(p), c, sp);
      }
  };
  each(m.spheres);
  each(m.shapes.planes);
  each(m.shapes.boxes);
  each(m.shapes.capsules);
  each(m.shapes.cylinders);
}

}  // namespace

ColliderBarrier::ColliderBarrier(const Model& m) {
  m_empty = m.spheres.empty() && m.shapes.empty();
  m_covered.resize(static_cast<size_t>(m.particle_count()));
  for (Eigen::Index p = 0; p < m.free.cols(); ++p)
    m_covered[static_cast<size_t>(p)] = m.free.col(p).minCoeff() > 0.0 ? 1 : 0;
}

double ColliderBarrier::energy(const Model& m, double t, const Matrix3X& x) const {
  if (m_empty) return 0.0;
  double e = 0.0;
  for_each_near(m, m_covered, t, x, [&](int p, const Collider& c, const SurfacePoint& sp) {
    e += m.mass[p] * kBarrierAcceleration / c.margin * barrier(sp.distance, c.margin);
  });
  return e;
}

void ColliderBarrier::contacts(const Model& m, double t, const Matrix3X& x,
                               std::vector<BarrierContact>& out, double h) const {
  out.clear();
  if (m_empty) return;
  for_each_near(m, m_covered, t, x, [&](int p, const Collider& c, const SurfacePoint& sp) {
    const double kappa = m.mass[p] * kBarrierAcceleration / c.margin;
    BarrierContact b;
    b.particle = p;
    b.normal = sp.normal;
    b.distance = sp.distance;
    b.force = -kappa * barrier_slope(sp.distance, c.margin);
    b.stiffness = kappa * barrier_curvature(sp.distance, c.margin);
    if (h > 0.0) b.collider_velocity = (c.displacement(t) - c.displacement(t - h)) / h;
    out.push_back(b);
  });
}

int ColliderBarrier::lift_out(const Model& m, double t, Matrix3X& x) const {
  if (m_empty) return 0;
  int lifted = 0;
  for_each_near(m, m_covered, t, x, [&](int p, const Collider& c, const SurfacePoint& sp) {
    if (sp.distance > 0.0) return;
    x.col(p) += (0.5 * c.margin - sp.distance) * sp.normal;
    ++lifted;
  });
  return lifted;
}

void ColliderBarrier::make_feasible(const Model& m, double t_end, double h, const Matrix3X& x0,
                                    Matrix3X& v) const {
  if (m_empty) return;
  auto each = [&](const auto& colliders) {
    for (const auto& c : colliders) {
      const Vector3 moved = (c.displacement(t_end) - c.displacement(t_end - h)) / h;
      for (Eigen::Index p = 0; p < x0.cols(); ++p) {
        if (!m_covered[static_cast<size_t>(p)]) continue;
        const Vector3 x = x0.col(p) + h * v.col(p);
        if (surface_point(c, t_end, x).distance <= 0.0) v.col(p) = moved;
      }
    }
  };
  each(m.spheres);
  each(m.shapes.planes);
  each(m.shapes.boxes);
  each(m.shapes.capsules);
  each(m.shapes.cylinders);
}

void ColliderBarrier::add_forces(const std::vector<BarrierContact>& contacts, Matrix3X& f) {
  for (const BarrierContact& b : contacts) f.col(b.particle) += b.force * b.normal;
}

void ColliderBarrier::friction_contacts(const Model& m, double t_end, double h, const Matrix3X& x0,
                                        std::vector<FrictionContact>& out) const {
  out.clear();
  if (m_empty) return;
  const double t0 = t_end - h;
  for_each_near(m, m_covered, t0, x0, [&](int p, const Collider& c, const SurfacePoint& sp) {
    if (c.friction == 0.0 || sp.distance <= 0.0) return;
    const double kappa = m.mass[p] * kBarrierAcceleration / c.margin;
    FrictionContact f;
    f.particle = p;
    f.normal = sp.normal;
    f.collider_velocity = (c.displacement(t_end) - c.displacement(t0)) / h;
    f.bound = c.friction * (-kappa * barrier_slope(sp.distance, c.margin));
    if (f.bound > 0.0) out.push_back(f);
  });
}

void StepFriction::start(std::vector<FrictionContact> contacts, double h) {
  m_contacts = std::move(contacts);
  m_h = h;
  m_eps = kFrictionSpeed * h;
}

Vector3 StepFriction::sliding(const FrictionContact& c, const Matrix3X& v) const {
  const Vector3 u = m_h * (v.col(c.particle) - c.collider_velocity);
  return u - c.normal.dot(u) * c.normal;
}

double StepFriction::energy(const Matrix3X& v) const {
  double e = 0.0;
  for (const FrictionContact& c : m_contacts)
    e += c.bound * friction_f0(sliding(c, v).norm(), m_eps);
  return e;
}

Vector3 StepFriction::force(const FrictionContact& c, const Matrix3X& v) const {
  const Vector3 u = sliding(c, v);
  const double y = u.norm();
  // f1(y) / y, finite as y -> 0 (2 / eps)
  const double per_length = y >= m_eps ? 1.0 / y : (2.0 - y / m_eps) / m_eps;
  return -(c.bound * per_length) * u;
}

void StepFriction::add_forces(const Matrix3X& v, Matrix3X& f) const {
  for (const FrictionContact& c : m_contacts) f.col(c.particle) += force(c, v);
}

double StepFriction::collider_power(const Matrix3X& v) const {
  double power = 0.0;
  for (const FrictionContact& c : m_contacts) power += force(c, v).dot(c.collider_velocity);
  return power;
}

void StepFriction::add_blocks(const Matrix3X& v, double scale, std::vector<int>& particles,
                              std::vector<Matrix3>& blocks) const {
  for (const FrictionContact& c : m_contacts) {
    const Vector3 u = sliding(c, v);
    const double y = u.norm();
    const Matrix3 tangent = Matrix3::Identity() - c.normal * c.normal.transpose();
    // mu lambda (f1' u^ u^T + f1 / y (P - u^ u^T)): below eps both are 2 / eps at y = 0
    const double per_length = y >= m_eps ? 1.0 / y : (2.0 - y / m_eps) / m_eps;
    const double along = y >= m_eps ? 0.0 : 2.0 / m_eps - 2.0 * y / (m_eps * m_eps);
    Matrix3 b = per_length * tangent;
    if (y > 0.0) {
      const Vector3 dir = u / y;
      b += (along - per_length) * dir * dir.transpose();
    }
    particles.push_back(c.particle);
    blocks.push_back((scale * c.bound) * b);
  }
}

}  // namespace cloth
