#pragma once
/// @file bullet_softbody.hpp
/// The "bullet-softbody" engine: Bullet's classic soft body, position-based link projection.

#include <memory>
#include <optional>

#include "cloth/model/scene.hpp"
#include "cloth/model/simulator.hpp"
#include "reference/bullet/bullet_options.hpp"
#include "reference/refusal.hpp"

namespace clothbench::reference {

/// Why bullet-softbody cannot model scene with options at step dt (naming the feature and the
/// keys to blame), or nullopt: what every Bullet engine refuses (bullet_scene_refusal), bad
/// options, sphere friction above 1. Builds nothing.
std::optional<Refusal> softbody_refusal(const BulletOptions& options, double dt,
                                        const cloth::Scene& scene);

/// A btSoftRigidDynamicsWorld with one cloth whose links are projected options.iterations
/// times per step. options.stiffness = "klst" uses options.klst for every link; "matched"
/// gives each link the kLST whose isolated link acts like the scene's spring constant at the
/// step dt and that iteration count (matched_link_klst; recomputed if step() gets another
/// dt). Measured: one link settles within 0.5% of m g / k at 1% strain (Bullet's projection
/// of squared lengths stiffens it by about half the strain), a hanging chain of 10 links
/// within +0.6% (bottom) to -3.7% (top link), the links' Gauss-Seidel coupling, which the
/// isolated-link formula ignores. The scene's spring damping has no counterpart here (kDP = 0: the
/// projection itself dissipates), so dissipated() books the energy balance of every step
/// (Dissipation::energy_balance): what the projection, the contacts and the air drag took out.
/// Its energy_error is therefore 0 by construction and not a measure of anything.
///
/// set_state (BulletCloth::set_state) makes the next step a function of (x, v, t, dt): a fresh
/// engine set to a run's state steps to the run's next state bit for bit, with and without
/// contact against a moving sphere (tests/reference/test_bullet_set_state.cpp). What Bullet 3.24
/// keeps between steps, and why none of it is state the map depends on here:
/// - m_q (the previous positions, from which the step takes the velocity, btSoftBody.cpp:2269)
///   is overwritten with m_x before anything reads it (predictMotion, btSoftBody.cpp:2128);
///   m_f is zeroed at the end of every step (:2270) and the rigid contacts are rebuilt
///   (cleared at :2199).
/// - The node tree's leaves are fattened by the node velocities and only re-inserted when a
///   node leaves its leaf (btSoftBody.cpp:2156-2164), and the tree is rebalanced every step
///   (:2202): its shape is history. The contact query visits every node whose leaf touches the
///   collider's box grown by the margin (SDF_RS, btSoftBody.cpp:4080-4104), a superset of the
///   nodes in contact that the exact SDF test then filters, so the contacts are the state's;
///   only their order in m_rcontacts is history. That order cannot matter against one
///   collider: PSolve_RContacts (btSoftBody.cpp:3885) moves only each contact's own node, and
///   a static or kinematic collider takes no impulse. Not a function of the state: a node
///   touching two colliders at once, corrected once per contact in an order set by the node
///   tree and the broadphase's pair list (unmeasured; none of the test scenes has it).
/// - A kinematic collider's velocity in the contacts (btSoftBodyInternals.h:1630,
///   btSoftBody.cpp:3905) comes from its previous pose (btRigidBody.cpp:105-121): set_state
///   places that pose at t (ColliderBodies::place_at).
/// - The sparse SDF caches cells computed from the shape alone (btSparseSDF.h BuildCell) and
///   drops old ones; a cell rebuilt later holds the same values.
/// - Clusters, pose matching, aerodynamics, pressure and volume are off (kMT = kLF = kDG =
///   kPR = kVC = 0), and the body never sleeps.
///
/// Throws std::invalid_argument with softbody_refusal's reason for a scene it cannot model (the
/// scenario loader refuses those first, so that is a programmer error).
/// @param dt  the step the engine will be run with (s), for "matched"
std::unique_ptr<cloth::Simulator> make_bullet_softbody(const BulletOptions& options, double dt,
                                                       const cloth::Scene& scene);

/// Why bullet-softbody has no cloth self-collision, for the harness to print.
inline constexpr const char* kSoftbodyNoSelfCollision =
    "bullet-softbody: not available: Bullet 3.24's classic soft body has no working cloth "
    "self-collision (vertex-face VF_SS skips a body's own pair, cluster CL_SS collides a body "
    "with itself only with CL_SELF, and CL_SS | CL_SELF matches no case of its collision "
    "switch); the run goes on without it";

/// False: bullet-softbody cannot keep a cloth's layers apart (kSoftbodyNoSelfCollision).
/// btSoftRigidDynamicsWorld collides each soft body with itself every step
/// (btSoftRigidDynamicsWorld.cpp:93-98), and btSoftBody::defaultCollisionHandler(btSoftBody*)
/// (btSoftBody.cpp:4158-4256) switches on (flags & SVSmask) of the pair: VF_SS (0x10) runs only
/// when the two bodies differ (btSoftBody.cpp:4174-4177), CL_SS (0x20) runs on one body only
/// with CL_SELF (0x40) also set (:4164-4167), and 0x20 | 0x40 = 0x60 is none of the case labels
/// 0x10, 0x20, 0x80 (btSoftBody.h:169-172), so it falls to the empty default. A scene with
/// cloth.self_collision = true runs on this engine without self-collision (make_bullet_softbody
/// ignores the flag). tests/reference/test_bullet_self_collision.cpp runs every combination.
bool softbody_self_collision_available();

/// Bullet's classic self-collision switches, for the test that shows they do nothing.
enum class SoftbodySelfFlags {
  none,       ///< the engine as make_bullet_softbody builds it
  vf_ss,      ///< collisions |= VF_SS
  cl_ss,      ///< generateClusters(0) (a cluster per face), collisions |= CL_SS
  cl_ss_self  ///< as cl_ss, and collisions |= CL_SELF
};

/// make_bullet_softbody's engine with flags added to the soft body's collision flags (and
/// clusters built for the cluster flags): evidence for softbody_self_collision_available, not
/// an engine of the harness. With vf_ss, btSoftBody::predictMotion builds the face tree
/// (btSoftBody.cpp:2108-2112), which never finishes on a mesh in several pieces
/// (btSoftBody.cpp:29-124): do not pass one. Throws like make_bullet_softbody.
std::unique_ptr<cloth::Simulator> make_bullet_softbody_with_flags(const BulletOptions& options,
                                                                  double dt,
                                                                  const cloth::Scene& scene,
                                                                  SoftbodySelfFlags flags);

}  // namespace clothbench::reference
