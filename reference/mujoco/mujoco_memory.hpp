#pragma once
/// @file mujoco_memory.hpp
/// What the mujoco engine's model costs in memory before it is built. MuJoCo 2.2.2 keeps
/// three dense arrays whose size grows with the square of the cloth: the tendon Jacobian
/// ten_J (#tendons by #dofs, mjxmacro.h:471), the constraint Jacobian efc_J and its
/// transpose (njmax by #dofs, mjxmacro.h:492-493) and efc_AR (njmax by njmax,
/// mjxmacro.h:504), each with an int column-index twin, plus a stack (nstack mjtNums) that its
/// constraint solver fills to about 2.3 #dofs njmax numbers in contact and its implicit
/// integrator to 13.1 #dofs^2 (dense #dofs by #dofs matrices; measured).

#include <cstdint>

#include "cloth/model/model.hpp"
#include "reference/mujoco/mujoco_options.hpp"

namespace clothbench::reference {

/// The most memory one mujoco engine may allocate (bytes): model, data buffer and stack.
constexpr double kMujocoMemoryLimit = 2.0 * 1024 * 1024 * 1024;

/// The sizes of the MuJoCo model of a cloth and the memory they take.
struct MujocoSize {
  int dofs = 0;            // slide joints: the free axes of the particles that are not handles
  int tendons = 0;         // one per spring
  int contacts = 0;        // nconmax: one per particle with a geom when there is a collider, else 0
  int rows = 0;            // njmax: constraint rows, contacts times the rows of one contact
  std::int64_t stack = 0;  // nstack (mjtNums) the model asks for
  double buffer_bytes = 0;  // mjData's main buffer (its dense arrays dominate)
  double model_bytes = 0;   // mjModel (mj_sizeModel), a linear estimate
  /// Everything allocated (bytes): model, buffer and stack.
  double total_bytes() const { return model_bytes + buffer_bytes + 8.0 * double(stack); }
};

/// The sizes of model as the mujoco engine builds it (mujoco_mjcf) with options.
MujocoSize mujoco_size(const cloth::Model& model, const MujocoOptions& options);

}  // namespace clothbench::reference
