#pragma once
/// @file engine_factory.hpp
/// Builds the engine an EngineSpec names, custom or Bullet, behind the Simulator interface
/// (what an engine cannot model, asked without building it: scenario/engine_refusal.hpp).

#include <memory>

#include "cloth/model/scene.hpp"
#include "cloth/model/simulator.hpp"
#include "harness/scenario/engine_refusal.hpp"
#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// A new engine of spec.kind at the initial state of scene, with the cloth's self_collision
/// replaced by the engine's own (self_collision_of). A scene the engine refuses
/// (engine_refusal) is a programmer error here: the loader refuses it first.
std::unique_ptr<cloth::Simulator> make_engine(const EngineSpec& spec, const cloth::Scene& scene);

}  // namespace clothbench
