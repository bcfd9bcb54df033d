#pragma once
/// @file engine_factory.hpp
/// Builds the engine an EngineSpec names, custom or Bullet, behind the Simulator interface,
/// and says without building anything what an engine cannot model.

#include <memory>
#include <optional>

#include "cloth/scene.hpp"
#include "cloth/simulator.hpp"
#include "harness/scenario.hpp"
#include "reference/bullet_options.hpp"

namespace clothbench {

/// Why an engine of spec cannot model scene (the feature, and the scenario keys to blame), or
/// nullopt when it can. Pure: nothing is constructed. The custom engine models every scene.
std::optional<reference::Refusal> engine_refusal(const EngineSpec& spec, const cloth::Scene& scene);

/// Throws UserError naming the engine, context (what was changed, e.g. "at dt = 0.002 s") and
/// the feature when engine_refusal refuses: for sweeps that change a loaded scene.
void require_engine_can_model(const EngineSpec& spec, const cloth::Scene& scene,
                              const std::string& context);

/// A new engine of spec.kind at the initial state of scene. A scene the engine refuses
/// (engine_refusal) is a programmer error here: the loader refuses it first.
std::unique_ptr<cloth::Simulator> make_engine(const EngineSpec& spec, const cloth::Scene& scene);

}  // namespace clothbench
