#pragma once
/// @file repulsion_order.hpp
/// Makes bullet-deformable's self-collision reproducible. Bullet applies its vertex-face
/// repulsions in a shuffled order (btSoftBody::applyRepulsionForce, btSoftBody.h), drawn from a
/// generator whose state is a file-level static (btSoftBody.h:39, `seed`) that nothing resets:
/// every engine in a process went on from where the ones before it left it, so a run's result
/// depended on what ran before it (measured: skirt's bullet-deformable-explicit ended 1.0 mm
/// elsewhere when lift_corners ran first in the same `clothbench check`).
///
/// The library calls that inline member through its procedure linkage table, so the
/// executable's own copy of it, emitted by repulsion_order.cpp alone, is the one every call
/// reaches, and its generator is the one reset_repulsion_order() puts back at Bullet's initial
/// state. Engines started in one thread one after another then repeat their runs exactly;
/// engines stepping at the same time in several threads (ensembles, -j) still share one
/// generator.

namespace clothbench::reference {

/// Puts the repulsion order's generator back at Bullet's initial state; returns false when
/// Bullet's calls do not reach the copy this resets (a Bullet linked so that its own copy
/// binds locally), and the order then depends on the process's history as before.
bool reset_repulsion_order();

}  // namespace clothbench::reference
