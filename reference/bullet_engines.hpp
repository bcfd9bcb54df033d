#pragma once
/// @file bullet_engines.hpp
/// The Bullet reference engines, built from the same scene as the custom engine.

#include <memory>

#include "cloth/scene.hpp"
#include "cloth/simulator.hpp"
#include "harness/scenario.hpp"

namespace clothbench::reference {

/// True for "bullet-deformable" and "bullet-softbody".
bool is_bullet_kind(const std::string& kind);

/// Builds a Bullet engine of spec.kind for scene. Throws std::invalid_argument, naming the
/// feature, for a scene the engine cannot model (e.g. structural and shear stiffness differ
/// for bullet-deformable).
std::unique_ptr<cloth::Simulator> make_bullet_engine(const EngineSpec& spec,
                                                     const cloth::Scene& scene);

}  // namespace clothbench::reference
