#pragma once
/// @file ensemble_member.hpp
/// Members of an ensemble: the same scene started from initial positions perturbed at
/// round-off level, so that a chaotic scene (one whose contact decisions flip under a 1e-13
/// change) can be gated by the distribution of its results instead of by one run.
///
/// Member 0 is the scene itself. Member m >= 1 moves the cloth's initial (rest) positions by a
/// deterministic pseudo-random offset of relative size kRoundOffPerturbation of the cloth's
/// extent, drawn from (seed, m) by a generator of our own (the same bits on every platform).
/// The cloth moves as a whole (a grid's centre, every vertex of a mesh): the engines place a
/// grid's particles from its centre and spacing and take the rest shape from the initial one,
/// so a rigid offset is what reaches every engine alike without touching its rest lengths,
/// and a flat cloth stays flat. Its contacts with the colliders start 1e-13 elsewhere, which
/// is what flips a chaotic scene's contact decisions. Held particles move with the rest.

#include <cstdint>

#include "cloth/model/scene.hpp"

namespace clothbench {

/// Largest offset of a perturbed member per axis, relative to the cloth's extent (m / m).
constexpr double kRoundOffPerturbation = 1e-13;

/// The scene of ensemble member `member` (0: scene unchanged) drawn with `seed`.
cloth::Scene perturbed_scene(const cloth::Scene& scene, int member, std::uint64_t seed = 0);

}  // namespace clothbench
