#pragma once
/// @file bullet_deformable.hpp
/// The "bullet-deformable" engine: Bullet's deformable world with the mass-spring force, the
/// physically equivalent reference for the custom engine.

#include <memory>
#include <optional>

#include "cloth/model/scene.hpp"
#include "cloth/model/simulator.hpp"
#include "reference/bullet/bullet_options.hpp"
#include "reference/refusal.hpp"

namespace clothbench::reference {

/// Why bullet-deformable cannot model scene with options (naming the feature and the keys to
/// blame), or nullopt: what every Bullet engine refuses (bullet_scene_refusal), structural and
/// shear stiffness that differ (one stiffness for both), and option combinations Bullet
/// ignores or mishandles. Builds nothing.
std::optional<Refusal> deformable_refusal(const BulletOptions& options, const cloth::Scene& scene);

/// A btDeformableMultiBodyDynamicsWorld with one cloth driven by
/// btDeformableMassSpringForce(k, c, true, k_bend) (damping along the spring, our formula)
/// and btDeformableGravityForce. options.implicit picks Bullet's backward Euler (with
/// options.line_search and options.projection) over its explicit scheme (elastic forces
/// symplectic, damping implicit).
///
/// Contacts are Bullet's node-versus-rigid contacts (SDF_RD | SDF_RDN), the counterpart of our
/// particle collisions, with the scene's margin as the soft body's margin. Bullet compares the
/// sphere's signed distance |x - c| - r (btSphereShape's own margin is its radius and is taken
/// out of the distance, not added) with the soft body's margin alone, so the contact shell is
/// r + margin as in our engine: the seed cloth rests at 1.0098 m on a 1.01 m shell. Its face
/// contacts (SDF_RDF, used by Bullet's demos) are left off: with them the implicit scheme blows
/// up on the seed scene at dt = 1e-3 and 4e-3 s, also with k = 200 N/m and also when the
/// cloth starts 5 cm clear of the sphere, so they, not the start in contact, are its cause.
///
/// A cloth starting inside the contact shell starts on it (start_positions). Bullet resolves
/// such an overlap with split impulses (at most m_deformable_maxErrorReduction = 0.1 m/s a
/// step), and its explicit scheme adds that split velocity to the initial guess of its
/// conjugate-gradient solve (btDeformableBodySolver::setupDeformableSolve). At the first step
/// of a cloth at rest the projected right-hand side of that solve is ~1e-13, and
/// btConjugateGradient stops relative to it (r.z < SIMD_EPSILON * min(1, b.M^-1 b)), so it
/// iterates into round-off; its loop does not project the preconditioned residual again, so
/// round-off in the contact node's constrained normal direction grows until the "negative
/// direction" exit and becomes that node's velocity: 0.47 m/s on the seed scene as recorded,
/// 54.9 m/s (1506 J) after a 1e-13 relative change of the damping. Starting on the shell, the
/// two runs end 1.5e-12 m apart after 3 s. The implicit scheme does not feed the split velocity
/// to its solve and was not affected.
///
/// Throws std::invalid_argument with deformable_refusal's reason for a scene it cannot model
/// (the scenario loader refuses those first, so that is a programmer error).
std::unique_ptr<cloth::Simulator> make_bullet_deformable(const BulletOptions& options,
                                                         const cloth::Scene& scene);

}  // namespace clothbench::reference
