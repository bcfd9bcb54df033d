#pragma once
/// @file sphere_collision.hpp
/// The report's sphere contact, applied after each step.
///
/// A particle closer to the centre than radius + margin is moved out to that shell along the
/// normal. If it approaches the sphere, its normal velocity relative to the sphere becomes
/// -C_R times what it was (a fixed, infinitely heavy sphere), and Coulomb friction takes up to
/// mu times the normal impulse from the tangential velocity. Held axes are left untouched.

#include <algorithm>
#include <vector>

#include "cloth/model/scene.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// The report's velocity response of a particle in contact, relative to the collider's
/// velocity: restitution on the approaching normal velocity, Coulomb friction on the
/// tangential one as an impulse bounded by the friction coefficient times the normal impulse.
struct ContactVelocity {
  Vector3 v;          // the new velocity (m/s), before the held-axis mask
  double keep = 1.0;  // the fraction of the tangential velocity friction left
};

/// The response of velocity vold at outward normal nrm against a collider moving at vs; for
/// a particle that is not approaching the surface, vold unchanged (keep 1).
inline ContactVelocity contact_velocity(const Vector3& vold, const Vector3& vs, const Vector3& nrm,
                                        const Collider& c) {
  const Vector3 vrel = vold - vs;
  const double vn = vrel.dot(nrm);
  if (vn >= 0) return {vold, 1.0};
  Vector3 vt = vrel - vn * nrm;
  const double impulse = (1.0 + c.restitution) * (-vn);  // normal velocity change (m/s)
  const double vt_norm = vt.norm();
  double keep = 1.0;
  if (c.friction > 0 && vt_norm > 0) keep = std::max(0.0, 1.0 - c.friction * impulse / vt_norm);
  vt *= keep;
  return {vs + vt - c.restitution * vn * nrm, keep};
}

/// What a contact pass touched: counted only for the particles in contact, so that a pass
/// over particles far from every collider costs nothing more.
struct ContactTally {
  int contacts = 0;                      // particle-collider contacts (within the shell)
  Vector3 impulse = Vector3::Zero();     // N s, the colliders' impulse on the cloth
  double collider_work = 0;              // J, each impulse dotted with its collider's velocity
  std::vector<char>* touched = nullptr;  // when given (#P), set for every particle counted

  /// Counts particle p's contact.
  void count(Eigen::Index p) {
    ++contacts;
    if (touched) (*touched)[static_cast<size_t>(p)] = 1;
  }
};

/// Resolves contact of every particle with every sphere at time t (s).
/// @param x     3 by #P positions (m), moved out of the spheres
/// @param v     3 by #P velocities (m/s), normal part replaced on approach
/// @param mass  #P masses (kg)
/// @param free  3 by #P, 1 for a free axis, 0 for a held one
/// @param tally when given, counts the contacts and adds their impulse and the work of the
///              spheres' motion (impulse . the sphere's velocity at t)
/// @return kinetic energy removed by the contacts (J; negative when a moving sphere adds some)
double resolve_sphere_contacts(const std::vector<Sphere>& spheres, double t, Matrix3X& x,
                               Matrix3X& v, const VectorX& mass, const Matrix3X& free,
                               ContactTally* tally = nullptr);

/// Deepest penetration below radius (m) of any particle into any sphere at time t; 0 if none.
double max_penetration(const std::vector<Sphere>& spheres, double t, const Matrix3X& x);

}  // namespace cloth
