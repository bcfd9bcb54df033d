#include "cloth/model/model.hpp"

#include <stdexcept>
#include <string>

namespace cloth {

Scene seed_scene(int per_edge) {
  Scene s;
  // the seed's total mass (625 kg) spread evenly: 1 kg a particle at 25 x 25
  s.cloth.nu = s.cloth.nv = per_edge;
  s.cloth.particle_mass = 625.0 / (double(per_edge) * per_edge);
  s.spheres.push_back(Sphere{});
  s.held.assign(static_cast<size_t>(s.particle_count()), 0);
  const ClothParams& c = s.cloth;
  for (int j : {0, c.nv - 1})
    for (int i : {0, c.nu - 1}) s.held[static_cast<size_t>(particle_index(c, i, j))] = kHoldAll;
  return s;
}

Matrix3X grid_positions(const ClothParams& c) {
  Matrix3X x(3, c.nu * c.nv);
  for (int j = 0; j < c.nv; ++j) {
    for (int i = 0; i < c.nu; ++i) {
      // a grid of one particle along a direction sits at the centre
      const double u = c.nu > 1 ? (double(i) / (c.nu - 1) - 0.5) * c.size_u : 0.0;
      const double v = c.nv > 1 ? (double(j) / (c.nv - 1) - 0.5) * c.size_v : 0.0;
      Vector3 p = c.center;
      p.x() += u;
      if (c.plane == Plane::xz)
        p.z() += v;
      else
        p.y() += v;
      x.col(j * c.nu + i) = p;
    }
  }
  return x;
}

Model build_model(const Scene& scene) {
  const ClothParams& c = scene.cloth;
  if (c.nu < 1 || c.nv < 1 || c.nu * c.nv < 2)
    throw std::invalid_argument("the cloth needs at least 1 x 2 particles, got " +
                                std::to_string(c.nu) + " x " + std::to_string(c.nv));
  const int n = c.nu * c.nv;
  Model m;
  m.nu = c.nu;
  m.nv = c.nv;
  m.x0 = grid_positions(c);
  const double pm = c.total_mass > 0 ? c.total_mass / n : c.particle_mass;
  if (!(pm > 0)) throw std::invalid_argument("particle mass must be positive");
  m.mass = VectorX::Constant(n, pm);
  m.inv_mass = VectorX::Constant(n, 1.0 / pm);
  m.free = Matrix3X::Ones(3, n);
  if (!scene.held.empty()) {
    if (static_cast<int>(scene.held.size()) != n)
      throw std::invalid_argument("held-axis mask has " + std::to_string(scene.held.size()) +
                                  " entries for " + std::to_string(n) + " particles");
    for (int p = 0; p < n; ++p)
      for (int a = 0; a < 3; ++a)
        if (scene.held[static_cast<size_t>(p)] & (1u << a)) {
          m.free(a, p) = 0.0;
          m.any_held = true;
        }
  }
  for (const Handle& h : scene.handles)
    for (int p : h.particles) {
      if (p < 0 || p >= n)
        throw std::invalid_argument("handle particle " + std::to_string(p) + " is not one of " +
                                    std::to_string(n));
      m.free.col(p).setZero();
      m.any_held = true;
    }
  m.springs = build_springs(c, m.x0);
  m.gravity = scene.gravity;
  m.air_drag = c.air_drag;
  m.wind = scene.wind;
  m.spheres = scene.spheres;
  m.shapes = scene.shapes;
  for (HalfSpace& h : m.shapes.planes) {
    if (!(h.normal.norm() > 0)) throw std::invalid_argument("a plane's normal must not be zero");
    h.normal.normalize();
  }
  m.handles = scene.handles;
  return m;
}

}  // namespace cloth
