#pragma once
/// @file mujoco_refusal.hpp
/// What the mujoco engine cannot model, said without building a MuJoCo model (the scenario
/// loader asks it before any engine is built).

#include <optional>

#include "cloth/model/scene.hpp"
#include "reference/mujoco/mujoco_options.hpp"
#include "reference/refusal.hpp"

namespace clothbench::reference {

/// Why the mujoco engine cannot model scene with options (naming the feature and the keys to
/// blame), or nullopt: restitution (MuJoCo's soft contacts have none), a contact margin of 0
/// (the particles' spheres need a radius), self-collision (particle pairs are excluded), and
/// a model whose dense arrays would pass kMujocoMemoryLimit. Builds no MuJoCo model.
std::optional<Refusal> mujoco_refusal(const MujocoOptions& options, const cloth::Scene& scene);

}  // namespace clothbench::reference
