#pragma once
/// @file engine_refusal.hpp
/// Says without building anything what an engine cannot model: the scenario loader refuses such
/// a scene before any engine is built (engines/engine_factory.hpp builds the ones it accepts).

#include <optional>
#include <string>

#include "cloth/model/scene.hpp"
#include "harness/scenario/scenario.hpp"
#include "reference/refusal.hpp"

namespace clothbench {

/// Why an explicit self_collision = true on a bullet-softbody engine is refused.
extern const char* const kSoftbodyNoSelfCollision;

/// Why an explicit self_collision = true on a mujoco engine is refused.
extern const char* const kMujocoNoSelfCollision;

/// Whether an engine keeps the cloth's layers apart.
enum class SelfCollision {
  off,           ///< neither the engine nor the cloth asks for it
  on,            ///< asked for, and the engine does it
  not_available  ///< the cloth asks for it and the engine cannot (bullet-softbody, mujoco)
};

/// "off", "on" or "not available" (as run.json and summary.csv write it).
const char* self_collision_name(SelfCollision s);

/// The engine's self-collision: its own self_collision key, else the cloth's. An explicit
/// engine-level true on an engine that cannot do it is refused by the loader first.
SelfCollision self_collision_of(const EngineSpec& spec, const cloth::ClothParams& cloth);

/// Why an engine of spec cannot model scene (the feature, and the scenario keys to blame), or
/// nullopt when it can. Pure: nothing is constructed. The custom engine models every scene
/// except bend_model = "hinge" with xpbd or projective; the Bullet engines refuse the hinge.
std::optional<reference::Refusal> engine_refusal(const EngineSpec& spec, const cloth::Scene& scene);

/// Throws UserError naming the engine, context (what was changed, e.g. "at dt = 0.002 s") and
/// the feature when engine_refusal refuses: for sweeps that change a loaded scene.
void require_engine_can_model(const EngineSpec& spec, const cloth::Scene& scene,
                              const std::string& context);

}  // namespace clothbench
