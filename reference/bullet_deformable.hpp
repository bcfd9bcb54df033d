#pragma once
/// @file bullet_deformable.hpp
/// The "bullet-deformable" engine: Bullet's deformable world with the mass-spring force, the
/// physically equivalent reference for the custom engine.

#include <memory>

#include "cloth/scene.hpp"
#include "cloth/simulator.hpp"
#include "harness/scenario.hpp"

namespace clothbench::reference {

/// A btDeformableMultiBodyDynamicsWorld with one cloth driven by
/// btDeformableMassSpringForce(k, c, true, k_bend) (damping along the spring, our formula)
/// and btDeformableGravityForce. options.implicit picks Bullet's backward Euler (with
/// options.line_search and options.projection) over its explicit scheme (elastic forces
/// symplectic, damping implicit). Contacts are Bullet's node-versus-rigid contacts
/// (SDF_RD | SDF_RDN), the counterpart of our particle collisions; its face contacts
/// (SDF_RDF, used by Bullet's demos) are left off: with them the implicit scheme goes unstable
/// on the seed scene at every dt tried and the explicit one without projection takes ~20 ms
/// a step. Throws std::invalid_argument naming the feature for what it
/// cannot model: structural and shear stiffness that differ (one stiffness for both), the
/// features check_bullet_scene refuses, and option combinations Bullet ignores or mishandles.
std::unique_ptr<cloth::Simulator> make_bullet_deformable(const BulletOptions& options,
                                                         const cloth::Scene& scene);

}  // namespace clothbench::reference
