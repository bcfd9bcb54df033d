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
/// Its energy_error is therefore 0 by construction and not a measure of anything. Throws
/// std::invalid_argument with softbody_refusal's reason for a scene it cannot model (the
/// scenario loader refuses those first, so that is a programmer error).
/// @param dt  the step the engine will be run with (s), for "matched"
std::unique_ptr<cloth::Simulator> make_bullet_softbody(const BulletOptions& options, double dt,
                                                       const cloth::Scene& scene);

}  // namespace clothbench::reference
