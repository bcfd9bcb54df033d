#pragma once
/// @file mujoco_mjcf.hpp
/// The scene as a MuJoCo 2.2.2 model, written as MJCF text (loaded from memory through
/// MuJoCo's virtual file system by mujoco_cloth.cpp, never from a file on disk).
///
/// The mapping: every particle is a body at its rest position with its mass, one slide joint
/// per free axis (x, y, z in that order; a held axis has none), a site the springs attach to
/// and a small sphere geom for contact; a handle particle is a mocap body without joints or
/// geom, moved each step. Every spring is a spatial tendon between two sites with the
/// spring's stiffness, damping and rest length (springlength), so its force is
/// -k (|d| - l0) d^ - c (v . d^) d^ as in the report. Colliders are geoms in the world, or in
/// mocap bodies when they move; particle geoms have contype 1 and conaffinity 0, colliders
/// the reverse, so no two particles ever meet and colliders never meet each other.

#include <string>
#include <vector>

#include "cloth/model/model.hpp"
#include "cloth/model/scene.hpp"
#include "reference/mujoco/mujoco_memory.hpp"
#include "reference/mujoco/mujoco_options.hpp"

namespace clothbench::reference {

/// Where each particle and collider lives in the MuJoCo model.
struct MjcfLayout {
  std::vector<std::array<int, 3>> dof;         // #P by 3: the slide joint's qpos (= qvel) index, -1
                                               // for a held axis
  std::vector<int> particle_mocap;             // #P: mocap index of a handle particle, else -1
  std::vector<int> handle_of;                  // #P: the handle moving the particle, else -1
  std::vector<const cloth::Collider*> moving;  // mocap 0 .. moving.size() - 1: the collider
  std::vector<cloth::Vector3> moving_start;    // the mocap body's position at t = 0 (m)
  double particle_radius = 0;                  // m, the particles' sphere geoms
};

/// The layout of model's particles and colliders.
MjcfLayout mjcf_layout(const cloth::Model& model);

/// True when the air drag's -c v part is the slide joints' damping, which MuJoCo evaluates at
/// every stage of its step (rk4: a force held over the step's four stages would make the step
/// first order), rather than applied by the adapter once a step (euler, implicit: so that
/// Euler's drag stays explicit, as symplectic Euler's is; MuJoCo's Euler and implicit
/// integrators would treat joint damping implicitly).
bool air_drag_in_joints(const MujocoOptions& options);

/// The MJCF text of model with step dt (s), the integrator and contact options, and the
/// memory sizes of size (nconmax, njmax, nstack); layout from mjcf_layout(model), whose
/// particle_radius it sets: half the smallest contact margin.
std::string mujoco_mjcf(const cloth::Model& model, const MujocoOptions& options, double dt,
                        const MujocoSize& size, MjcfLayout& layout);

}  // namespace clothbench::reference
