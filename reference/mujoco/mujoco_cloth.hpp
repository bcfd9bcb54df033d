#pragma once
/// @file mujoco_cloth.hpp
/// The mujoco engine: the scene built as a MuJoCo 2.2.2 model (mujoco_mjcf.hpp) and stepped
/// by MuJoCo's own integrators (mujoco_options.hpp) and soft-constraint contacts. The only
/// code that includes MuJoCo is in reference/mujoco/.
///
/// What MuJoCo lacks is added the way the Bullet adapters add it: the scene's air drag and
/// wind, -c (v - w) on every free axis, as a force applied (qfrc_applied) from the state at
/// the start of each step (explicit, and held fixed over rk4's stages). Handle particles and
/// moving colliders are mocap bodies put on their path at every step's start; MuJoCo gives
/// mocap bodies no velocity, so a spring to a handle is damped as if the handle stood still,
/// and a moving collider drags nothing by friction.
///
/// set_state writes qpos and qvel of the slide joints, the time and the mocap bodies' poses,
/// and clears the constraint solver's warm start (qacc_warmstart), so that the next step is
/// a function of the state alone; held axes and handle particles have no joint and stay where
/// the scene puts them, whatever x says there.

#include <memory>
#include <optional>

#include "cloth/model/model.hpp"
#include "cloth/model/scene.hpp"
#include "cloth/model/simulator.hpp"
#include "reference/mujoco/mujoco_memory.hpp"
#include "reference/mujoco/mujoco_options.hpp"
#include "reference/mujoco/mujoco_refusal.hpp"

namespace clothbench::reference {

/// A MuJoCo engine at the initial state of scene with step dt (s; step() may be given
/// another). Throws std::invalid_argument with mujoco_refusal's reason for a scene it cannot
/// model, std::runtime_error when MuJoCo refuses the model.
std::unique_ptr<cloth::Simulator> make_mujoco_cloth(const MujocoOptions& options, double dt,
                                                    const cloth::Scene& scene);

/// What a built MuJoCo model measures, for the memory table.
struct MujocoMeasure {
  MujocoSize size;          // the estimate the engine was built from
  double model_bytes = 0;   // mj_sizeModel
  double buffer_bytes = 0;  // mjData's nbuffer
  double stack_bytes = 0;   // mjData's nstack * sizeof(mjtNum)
  double stack_used = 0;    // bytes of stack used at most so far (maxuse_stack)
};

/// The measured sizes of engine, which must come from make_mujoco_cloth.
MujocoMeasure mujoco_measure(const cloth::Simulator& engine);

}  // namespace clothbench::reference
