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
/// blame), or nullopt: what every Bullet engine refuses (bullet_scene_refusal), a mesh whose
/// triangles are not one piece joined by shared edges (Bullet 3.24's face tree never finishes
/// on it, with or without self-collision: the first step hangs), structural and
/// shear stiffness that differ (one stiffness for both), option combinations Bullet
/// ignores or mishandles, a negative repulsion_stiffness or collision_margin, and, with
/// scene.cloth.self_collision, a self-collision margin (self_collision_margin) that is not
/// positive or differs from the colliders' margin (Bullet has one margin for both). Builds
/// nothing.
std::optional<Refusal> deformable_refusal(const BulletOptions& options, const cloth::Scene& scene);

/// The soft body's collision margin with self-collision on (m): options.collision_margin, or
/// half of scene.cloth.thickness when that is 0. Bullet's self-contact test (CollideFF_DD)
/// takes twice the margin as its proximity distance (btSoftBody.cpp:4237) and its repulsion
/// pushes a node until it is that far from the face's plane (btSoftBody.h:1342-1357), so half
/// the thickness keeps the layers about one thickness apart.
double self_collision_margin(const BulletOptions& options, const cloth::Scene& scene);

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
/// Self-collision (scene.cloth.self_collision; off: none of this is done and the engine is
/// what it was without these options): Bullet's own, both VF_DD and setSelfCollision(true)
/// (btSoftBody.cpp:4065), with self_collision_margin as the body's margin. After the step's
/// solve, CollideFF_DD pairs the faces of the body's face tree and records each node within
/// 2 x margin of a face's plane and over it (proximityTest, btSoftBodyInternals.h:66); it
/// skips face pairs that share a node (btSoftBodyInternals.h:1992-2001) and tests vertex
/// against face only, never edge against edge. Each contact gets a repulsion impulse
/// min(repulsion_stiffness dt d, m (0.1 d / dt - v_n)) plus half the approach momentum
/// (btSoftBody::applyRepulsionForce, btSoftBody.h:1317-1390), applied in an order shuffled
/// from a seed that is never reset (btSoftBody.h:39); up to 5 rounds of vertex-face CCD then
/// re-apply the inelastic part to the same discrete contacts
/// (btDeformableMultiBodyDynamicsWorld.cpp:176-258). repulsion_stiffness (N/m) is Bullet's
/// m_repulsionStiffness, set with setSpringStiffness; Bullet's default is 0.5
/// (btSoftBody.cpp:230), and so is ours. setSpringStiffness also writes the kLST of every
/// link's material (btSoftBody.cpp:3453-3460), which only the classic solver reads:
/// btDeformableMassSpringForce uses its own stiffness (btDeformableMassSpringForce.h:111).
/// As read, not measured: the face-pair traversal (btDbvt::selfCollideT, btDbvt.h:887-947)
/// enters a subtree's own pairs only when its normal-cone angle exceeds pi
/// (calculateNormalCone, btSoftBody.cpp:2611-2640), so layers in a subtree of nearly parallel
/// faces are not tested against each other. Measured (test_bullet_self_collision.cpp): the
/// flat top layer of a folded strip falls onto its held bottom layer and rests 2 x margin
/// above it (3.998-4.000 mm for a 2 mm margin), while nodes of the fold still pass through the
/// bottom layer (8 crossings). The self-contact friction is kDF x kDF of the body
/// (btSoftBodyInternals.h:2034), and kDF is 1 here because it also scales the colliders'
/// friction: cloth.self_friction is not mapped (Bullet's self-contact friction is 1).
/// Self-contacts count as contacts for unbooked().
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
/// set_state (BulletCloth::set_state) makes the next step a function of (x, v, t, dt) with
/// self-collision off: a fresh engine set to a run's state steps to the run's next state bit
/// for bit, explicit and implicit, with and without contact against a moving sphere
/// (tests/reference/test_bullet_set_state.cpp). What Bullet 3.24 keeps between steps:
/// - Read from the last step, hence set: m_q, the positions the explicit scheme's spring force
///   is evaluated at (btDeformableMassSpringForce.h:109) before the step sets it, left equal to
///   m_x by the last step (btDeformableBodySolver.cpp:535-537); m_vn, the implicit scheme's
///   v_n (btDeformableBodySolver.cpp:349-350), left equal to m_v; a kinematic collider's
///   previous pose, from which Bullet takes its velocity (btRigidBody.cpp:105-121) and at which
///   it predicts contacts (btSoftBody.cpp:2787): ColliderBodies::place_at.
/// - Rebuilt every step, hence no history: the backup velocities, the solve's dv, ddv and
///   residual (zeroed in reinitialize, btDeformableBodySolver.cpp:236-241; backupVelocity at
///   the start of solveConstraints, :317-328), so there is no warm start: the explicit CG
///   starts from this step's contact dv (setupDeformableSolve, :330-360), the Newton step from
///   0; the contacts (cleared in predictMotion, :411-415), the constraints and Lagrange
///   multipliers (btDeformableContactProjection.cpp:625-638); split velocities and constrained
///   flags (btDeformableBodySolver.cpp:470-471); the node and face trees' boxes, refitted from
///   the nodes (:475-479, btSoftBody.h:1257-1306) on a topology fixed by the connectivity alone
///   (node insertion order, face tree btSoftBody.cpp:29-124), so contacts come in the same
///   order.
/// - Kept but not read by the step: m_maxSpeedSquared, the world's m_internalTime (read only
///   by solver callbacks, none here), sleeping state (the body never sleeps).
/// - Not settable, with self-collision on: the repulsion impulses are applied in an order
///   shuffled by a generator whose seed is a file-static variable of btSoftBody.h (:39,
///   advanced at :1325-1331), never reset and not reachable from here. With self-contacts the
///   step is therefore not a function of the state: the same state steps to states that differ
///   by the order of those impulses (unmeasured). Without self-contacts the shuffle draws
///   nothing.
/// - Not a function of the state either: a node touching two colliders at once, whose
///   contacts are solved in turn in the order of the broadphase's pair list, which is history
///   (unmeasured; none of the test scenes has it).
///
/// Throws std::invalid_argument with deformable_refusal's reason for a scene it cannot model
/// (the scenario loader refuses those first, so that is a programmer error).
std::unique_ptr<cloth::Simulator> make_bullet_deformable(const BulletOptions& options,
                                                         const cloth::Scene& scene);

}  // namespace clothbench::reference
