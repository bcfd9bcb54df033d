#pragma once
/// @file engine_factory.hpp
/// Builds the engine an EngineSpec names, custom or Bullet, behind the Simulator interface.

#include <memory>
#include <string>
#include <vector>

#include "cloth/scene.hpp"
#include "cloth/simulator.hpp"
#include "harness/scenario.hpp"

namespace clothbench {

/// The engine kinds clothbench knows: "custom", "bullet-deformable", "bullet-softbody".
const std::vector<std::string>& engine_kinds();

/// A new engine of spec.kind at the initial state of scene. Throws std::invalid_argument
/// naming the feature when that kind cannot model the scene.
std::unique_ptr<cloth::Simulator> make_engine(const EngineSpec& spec, const cloth::Scene& scene);

}  // namespace clothbench
