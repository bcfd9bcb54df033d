#pragma once
/// @file colliders.hpp
/// Contact with the rigid shapes of a scene other than spheres: half-spaces, axis-aligned boxes,
/// capsules and y-axis cylinders, each written as a signed distance and its outward normal.
///
/// The response is the report's sphere contact (sphere_collision.hpp) for any shape: a particle
/// closer to the surface than the margin is moved out to that shell along the normal; if it
/// approaches the collider, its normal velocity relative to the collider becomes -C_R times
/// what it was, and Coulomb friction takes up to mu times the normal impulse from the
/// tangential relative velocity. Friction shortens the step's travel along the surface relative
/// to the collider by the same fraction as that velocity, so that it stops the motion and not
/// only the velocity (a particle sticking on an incline stays put). Held axes are untouched.

#include <cstdint>
#include <vector>

#include "cloth/contact/sphere_collision.hpp"
#include "cloth/model/scene.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// Signed distance (m, negative inside) of a point to a surface, and the outward unit normal
/// there (for box, capsule and cylinder: from the closest surface point).
struct SurfacePoint {
  double distance = 0;
  Vector3 normal = Vector3::UnitY();
};

/// Each shape at time t (s), moved by its motion.
SurfacePoint surface_point(const HalfSpace& s, double t, const Vector3& x);
SurfacePoint surface_point(const Box& s, double t, const Vector3& x);
SurfacePoint surface_point(const Capsule& s, double t, const Vector3& x);
SurfacePoint surface_point(const Cylinder& s, double t, const Vector3& x);
SurfacePoint surface_point(const Sphere& s, double t, const Vector3& x);

/// Resolves contact of every particle with every shape at the end of a step of h s, at time t.
/// @param x0    3 by #P positions at the step's start (m)
/// @param x     3 by #P positions (m), moved out of the shapes
/// @param v     3 by #P velocities (m/s)
/// @param free  3 by #P, 1 for a free axis, 0 for a held one
/// @param mass  #P masses (kg)
/// @param tally counts the contacts and adds their impulse and the work of the shapes' motion
///              (impulse . the shape's velocity over the step)
/// @return particle-shape distance tests made (#P per shape)
std::int64_t resolve_shape_contacts(const Shapes& shapes, double t, double h, const Matrix3X& x0,
                                    Matrix3X& x, Matrix3X& v, const Matrix3X& free,
                                    const VectorX& mass, ContactTally& tally);

/// Deepest penetration (m) of any particle below the surface of any collider (spheres included)
/// at time t; 0 if none.
double max_penetration(const std::vector<Sphere>& spheres, const Shapes& shapes, double t,
                       const Matrix3X& x);

}  // namespace cloth
