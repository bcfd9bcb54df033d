#pragma once
/// @file contact_constraints.hpp
/// Contacts held inside implicit Euler's solve (newton = "line-search", contacts = "in-solve").
///
/// A free particle touching a collider that neither bounces nor rubs (restitution 0, friction
/// 0) and not leaving it, or heading into one, gets its velocity's component along the collider's
/// outward normal n fixed for the step: the unknowns are filtered by I - n n^T, as held axes are by
/// their mask (Baraff and Witkin 1998, 5.3). The fixed normal velocity lands a particle above the
/// contact shell on it at the step's end and keeps one in the shell where it is; the contact
/// pass after the step still resolves everything else (friction, restitution, particles on two
/// colliders, penetration left by the step's curvature). The constraint's impulse is the
/// normal part of the backward-Euler residual at the solution; a contact whose impulse pulls
/// the particle in (adhesion) is released for the next step.

#include <vector>

#include "cloth/model/model.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// One particle's velocity held along a normal for a step.
struct ContactConstraint {
  int particle = 0;
  Vector3 normal = Vector3::UnitY();  // outward unit normal of the collider at the step's start
  double normal_velocity = 0;         // m/s, the fixed n . v
  Vector3 collider_velocity = Vector3::Zero();  // m/s, the collider's mean over the step
};

/// The contacts of a step from (x0, v0) of h seconds that ends at t_end, at most one per
/// particle (the first collider in the scene's order: spheres, planes, boxes, capsules,
/// cylinders).
/// @param released  #P flags (or empty): particles whose last contact pulled them in, held only
///                  if heading into a collider
/// @param out       written
void find_contact_constraints(const Model& m, double t_end, double h, const Matrix3X& x0,
                              const Matrix3X& v0, const std::vector<char>& released,
                              std::vector<ContactConstraint>& out);

/// u_p -= (n . u_p) n for every constrained particle p (3 by #P).
void remove_normal_parts(const std::vector<ContactConstraint>& contacts, Matrix3X& u);

}  // namespace cloth
