#pragma once
/// @file test_scenes.hpp
/// Small scenes the physics tests share.

#include "cloth/forces/energies.hpp"
#include "cloth/integrators/mass_spring_cloth.hpp"
#include "cloth/model/model.hpp"
#include "cloth/model/scene.hpp"

namespace clothbench::test {

/// A soft n x n cloth, 1 m square, hanging from its two corners of edge v = 0, no contact.
inline cloth::Scene small_cloth(int n = 5, double k = 20.0, double damping = 0.5) {
  cloth::Scene s;
  s.cloth.nu = n;
  s.cloth.nv = n;
  s.cloth.size_u = 1.0;
  s.cloth.size_v = 1.0;
  s.cloth.center = {0.0, 0.0, 0.0};
  s.cloth.plane = cloth::Plane::xz;
  s.cloth.particle_mass = 0.1;
  s.cloth.k_structural = k;
  s.cloth.k_shear = k;
  s.cloth.k_bend = k;
  s.cloth.damping = damping;
  s.held.assign(static_cast<size_t>(n * n), 0);
  s.held[0] = cloth::kHoldAll;
  s.held[static_cast<size_t>(n - 1)] = cloth::kHoldAll;
  return s;
}

/// One free particle of mass m on a spring k (damper c) along x, 0.5 m long, to a pinned one
/// (particle 0), no gravity.
inline cloth::Scene one_spring(double m, double k, double c) {
  cloth::Scene s;
  s.cloth.nu = 2;
  s.cloth.nv = 1;
  s.cloth.size_u = 0.5;
  s.cloth.particle_mass = m;
  s.cloth.k_structural = k;
  s.cloth.k_shear = s.cloth.k_bend = 0.0;
  s.cloth.damping = c;
  s.gravity.setZero();
  s.held = {cloth::kHoldAll, 0};
  return s;
}

/// A vertical chain of n free particles of mass m below a pinned one, springs k, spacing l.
inline cloth::Scene chain(int n, double m, double k, double l, double damping, double g) {
  cloth::Scene s;
  s.cloth.nu = 1;
  s.cloth.nv = n + 1;
  s.cloth.size_u = 0.0;
  s.cloth.size_v = n * l;
  s.cloth.center = {0.0, 0.0, 0.0};
  s.cloth.plane = cloth::Plane::xy;
  s.cloth.particle_mass = m;
  s.cloth.k_structural = k;
  s.cloth.k_shear = 0.0;
  s.cloth.k_bend = 0.0;
  s.cloth.damping = damping;
  s.gravity = {0.0, -g, 0.0};
  s.held.assign(static_cast<size_t>(n + 1), 0);
  s.held[static_cast<size_t>(n)] = cloth::kHoldAll;  // the top particle, j = nv - 1
  return s;
}

/// A free 8 x 8 cloth of 6.4 kg, 1 m square, springs 200 N/m, lying flat at rest on the contact
/// shell (y = margin) of a floor through the origin, under gravity g: every particle sees the
/// same thing, so no spring ever stretches. The floor moves at velocity u with friction mu.
inline cloth::Scene cloth_on_floor(double g, const cloth::Vector3& u = cloth::Vector3::Zero(),
                                   double mu = 0.0) {
  cloth::Scene s = small_cloth(8, 200.0, 0.5);
  s.held.clear();
  cloth::HalfSpace floor;
  floor.velocity = u;
  floor.friction = mu;
  s.cloth.center = {0.0, floor.margin, 0.0};
  s.shapes.planes.push_back(floor);
  s.gravity = {0.0, -g, 0.0};
  return s;
}

/// Kinetic + gravity + elastic energy of the cloth's state (J).
inline double mechanical_energy(const cloth::MassSpringCloth& c) {
  return cloth::compute_energies(c.model(), c.positions(), c.velocities()).total();
}

}  // namespace clothbench::test
