#include "harness/run/metrics.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "cloth/contact/colliders.hpp"
#include "cloth/contact/sphere_collision.hpp"
#include "cloth/forces/energies.hpp"
#include "cloth/forces/spring_forces.hpp"
#include "cloth/model/constants.hpp"

namespace clothbench {

using cloth::Matrix3X;

namespace {

// fills the cells of a raster whose centres lie inside triangle (a, b, c), in cell units
void fill_triangle(std::vector<unsigned char>& mask, int w, int h, const double* a, const double* b,
                   const double* c) {
  const double area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  if (area2 == 0.0) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a[0], b[0], c[0]}))));
  const int x1 = std::min(w - 1, static_cast<int>(std::ceil(std::max({a[0], b[0], c[0]}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a[1], b[1], c[1]}))));
  const int y1 = std::min(h - 1, static_cast<int>(std::ceil(std::max({a[1], b[1], c[1]}))));
  const double s = area2 > 0 ? 1.0 : -1.0;
  for (int j = y0; j <= y1; ++j) {
    const double py = j + 0.5;
    for (int i = x0; i <= x1; ++i) {
      const double px = i + 0.5;
      // edge functions, all of the triangle's orientation sign when inside
      const double e0 = s * ((b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]));
      const double e1 = s * ((c[0] - b[0]) * (py - b[1]) - (c[1] - b[1]) * (px - b[0]));
      const double e2 = s * ((a[0] - c[0]) * (py - c[1]) - (a[1] - c[1]) * (px - c[0]));
      if (e0 >= 0 && e1 >= 0 && e2 >= 0) mask[static_cast<size_t>(j) * w + i] = 1;
    }
  }
}

}  // namespace

double shadow_area(const cloth::Model& model, const Eigen::Vector3d& gravity, const Matrix3X& x) {
  if (model.triangles.empty()) return 0.0;
  if (!x.allFinite()) return NAN;
  // an orthonormal basis (e1, e2) of the plane normal to gravity (y up without gravity)
  const Eigen::Vector3d n =
      gravity.norm() > 0 ? Eigen::Vector3d(-gravity.normalized()) : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d helper =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d e1 = (helper - helper.dot(n) * n).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  const Eigen::Index np = x.cols();
  Eigen::Matrix<double, 2, Eigen::Dynamic> q(2, np);
  for (Eigen::Index p = 0; p < np; ++p) q.col(p) << e1.dot(x.col(p)), e2.dot(x.col(p));
  const Eigen::Vector2d lo = q.rowwise().minCoeff(), hi = q.rowwise().maxCoeff();
  const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  if (extent <= 0) return 0.0;
  const double cell = extent / kShadowResolution;
  const int w = static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)) + 1;
  const int h = static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)) + 1;
  std::vector<unsigned char> mask(static_cast<size_t>(w) * h, 0);
  for (Eigen::Index p = 0; p < np; ++p) q.col(p) = (q.col(p) - lo) / cell;
  for (const cloth::Triangle& tri : model.triangles)
    fill_triangle(mask, w, h, q.col(tri[0]).data(), q.col(tri[1]).data(), q.col(tri[2]).data());
  size_t covered = 0;
  for (unsigned char c : mask) covered += c;
  return static_cast<double>(covered) * cell * cell;
}

FrameMetrics frame_metrics(const cloth::Model& model, double t, const Matrix3X& x,
                           const Matrix3X& v, const EnergyBooks& books, double e0,
                           const cloth::SelfIntersectionMeter* meter) {
  FrameMetrics m;
  m.t = t;
  const cloth::Energies e = cloth::compute_energies(model, x, v);
  m.kinetic = e.kinetic;
  m.gravity_potential = e.gravity_potential;
  m.elastic_potential = e.elastic_potential;
  m.dissipated = books.dissipated;
  m.contact_work = books.contact_work;
  m.collider_work = books.collider_work;
  m.unbooked = books.unbooked;
  m.handle_work = books.handle_work;
  m.total_energy = e.total();
  m.energy_error = energy_error(m.total_energy, books, e0);
  const cloth::StrainStats s = cloth::strain_stats(model.springs, x);
  m.max_strain = s.max_abs;
  m.mean_strain = s.mean_abs;
  m.max_stretch = s.max_stretch;
  m.max_compression = s.max_compression;
  if (meter) {
    // a measurement cut short by its work budget (a blown-up state) is a bound, not a figure
    const cloth::SelfIntersection si = meter->measure(x);
    m.self_intersections = si.complete ? si.crossings : -1;
    m.min_self_distance = si.complete ? si.min_distance : NAN;
  }
  m.com = (x * model.mass) / model.mass.sum();
  m.min_y = x.row(1).minCoeff();
  m.max_penetration = cloth::max_penetration(model.spheres, model.shapes, t, x);
  m.shadow_area = shadow_area(model, model.gravity, x);
  return m;
}

EnergyScale::EnergyScale(const cloth::Model& model) {
  const Eigen::Vector3d extent = model.x0.rowwise().maxCoeff() - model.x0.rowwise().minCoeff();
  m_weight_extent = model.mass.sum() * model.gravity.norm() * extent.maxCoeff();
}

void EnergyScale::observe(double kinetic, double elastic) {
  m_kinetic = std::max(m_kinetic, kinetic);
  m_elastic = std::max(m_elastic, elastic);
}

namespace {

// the net force on particle p less what the spheres can push back with
Eigen::Vector3d unbalanced_force(const cloth::Model& model, double t, const Matrix3X& x, int p,
                                 Eigen::Vector3d f) {
  for (const cloth::Sphere& s : model.spheres) {
    const Eigen::Vector3d d = x.col(p) - s.center_at(t);
    const double dist = d.norm();
    if (!(dist > 0) || dist > s.radius + 2.0 * s.margin) continue;
    const Eigen::Vector3d n = d / dist;
    const double fn = f.dot(n);
    if (fn >= 0) continue;  // pulled away: the sphere cannot hold it
    // the normal push cancels fn; friction takes up to mu |fn| of the tangential rest
    f -= fn * n;
    const double ft = f.norm();
    const double grip = s.friction * -fn;
    f = ft > grip ? Eigen::Vector3d(f * (1.0 - grip / ft)) : Eigen::Vector3d::Zero();
  }
  return f;
}

}  // namespace

double static_residual(const cloth::Model& model, double t, const Matrix3X& x, const Matrix3X& v) {
  const double g = model.gravity.norm();
  if (!(g > 0)) return NAN;
  Matrix3X f = Matrix3X::Zero(3, x.cols()), buf(3, x.cols());
  cloth::add_spring_forces(model.springs, x, v, f, buf);
  model.add_drag(v, f);
  double worst = 0;
  for (int p = 0; p < static_cast<int>(x.cols()); ++p) {
    if (model.free.col(p).isZero()) continue;
    const Eigen::Vector3d net = f.col(p) + model.mass[p] * model.gravity;
    const Eigen::Vector3d left =
        unbalanced_force(model, t, x, p, net).cwiseProduct(model.free.col(p));
    const double r = left.norm() / (model.mass[p] * g);
    if (!(r <= worst)) worst = r;  // NaN propagates
  }
  return worst;
}

Divergence divergence(const Matrix3X& x, const FrameMetrics& m, const Matrix3X& x_ref,
                      const FrameMetrics& m_ref) {
  Divergence d;
  d.t = m.t;
  const Eigen::VectorXd dist2 = (x - x_ref).colwise().squaredNorm().transpose();
  d.rms_distance = std::sqrt(dist2.mean());
  d.max_distance = std::sqrt(dist2.maxCoeff());
  d.com_distance = (m.com - m_ref.com).norm();
  d.energy_difference = m.total_energy - m_ref.total_energy;
  d.shadow_area_difference = m.shadow_area - m_ref.shadow_area;
  return d;
}

double support_area(const std::vector<double>& disk_radii,
                    const std::vector<cloth::Sphere>& spheres, bool horizontal,
                    const std::vector<cloth::Cylinder>& cylinders) {
  double a = 0.0;
  for (double r : disk_radii) a += cloth::kPi * r * r;
  if (a > 0 || !horizontal) return a;
  // a cylinder's top (the Cusick disk) is the support when there is one
  for (const cloth::Cylinder& c : cylinders)
    if (!c.moves()) a += cloth::kPi * c.radius * c.radius;
  if (a > 0) return a;
  // a sphere is a support only while it stays put under the cloth
  for (const cloth::Sphere& s : spheres)
    if (!s.moves()) a += cloth::kPi * s.radius * s.radius;
  return a;
}

double drape_coefficient(double shadow, double support, double cloth_area) {
  return (shadow - support) / (cloth_area - support);
}

}  // namespace clothbench
