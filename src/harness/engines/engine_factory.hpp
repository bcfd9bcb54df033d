#pragma once
/// @file engine_factory.hpp
/// Builds the engine an EngineSpec names, custom or Bullet, behind the Simulator interface
/// (what an engine cannot model, asked without building it: scenario/engine_refusal.hpp).

#include <memory>

#include "cloth/model/scene.hpp"
#include "cloth/model/simulator.hpp"
#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// Whether an engine keeps the cloth's layers apart.
enum class SelfCollision {
  off,           ///< neither the engine nor the cloth asks for it
  on,            ///< asked for, and the engine does it
  not_available  ///< the cloth asks for it and the engine cannot (bullet-softbody)
};

/// "off", "on" or "not available" (as run.json and summary.csv write it).
const char* self_collision_name(SelfCollision s);

/// The engine's self-collision: its own self_collision key, else the cloth's. An explicit
/// engine-level true on an engine that cannot do it is refused by the loader first.
SelfCollision self_collision_of(const EngineSpec& spec, const cloth::ClothParams& cloth);

/// A new engine of spec.kind at the initial state of scene, with the cloth's self_collision
/// replaced by the engine's own (self_collision_of). A scene the engine refuses
/// (engine_refusal) is a programmer error here: the loader refuses it first.
std::unique_ptr<cloth::Simulator> make_engine(const EngineSpec& spec, const cloth::Scene& scene);

}  // namespace clothbench
