#pragma once
/// @file sphere_collision.hpp
/// The report's sphere contact, applied after each step.
///
/// A particle closer to the centre than radius + margin is moved out to that shell along the
/// normal. If it approaches the sphere, its normal velocity relative to the sphere becomes
/// -C_R times what it was (a fixed, infinitely heavy sphere), and Coulomb friction takes up to
/// mu times the normal impulse from the tangential velocity. Held axes are left untouched.

#include <vector>

#include "cloth/scene.hpp"
#include "cloth/types.hpp"

namespace cloth {

/// What a contact pass touched: counted only for the particles in contact, so that a pass
/// over particles far from every collider costs nothing more.
struct ContactTally {
  int contacts = 0;                   // particle-collider contacts (within the shell)
  Vector3 impulse = Vector3::Zero();  // N s, the colliders' impulse on the cloth
};

/// Resolves contact of every particle with every sphere at time t (s).
/// @param x     3 by #P positions (m), moved out of the spheres
/// @param v     3 by #P velocities (m/s), normal part replaced on approach
/// @param mass  #P masses (kg)
/// @param free  3 by #P, 1 for a free axis, 0 for a held one
/// @param tally when given, counts the contacts and adds their impulse
/// @return kinetic energy removed by the contacts (J; negative when a moving sphere adds some)
double resolve_sphere_contacts(const std::vector<Sphere>& spheres, double t, Matrix3X& x,
                               Matrix3X& v, const VectorX& mass, const Matrix3X& free,
                               ContactTally* tally = nullptr);

/// Deepest penetration below radius (m) of any particle into any sphere at time t; 0 if none.
double max_penetration(const std::vector<Sphere>& spheres, double t, const Matrix3X& x);

}  // namespace cloth
