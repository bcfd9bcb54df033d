#include "reference/mujoco/mujoco_memory.hpp"

namespace clothbench::reference {

MujocoSize mujoco_size(const cloth::Model& model, const MujocoOptions& options) {
  MujocoSize s;
  const int n = model.particle_count();
  s.dofs = static_cast<int>(model.free.sum());
  s.tendons = model.springs.count();
  // every particle that moves has a geom and may touch one collider at a time
  const bool any_collider = !model.spheres.empty() || !model.shapes.empty();
  int moving = 0;
  for (int p = 0; p < n; ++p) moving += model.free.col(p).sum() > 0 ? 1 : 0;
  s.contacts = any_collider ? moving : 0;
  // a frictional contact has 4 rows in a pyramidal cone (2 (condim - 1)), 3 in an elliptic one
  s.rows = s.contacts * (options.elliptic ? 3 : 4);
  // the stack, with room: the constraint solver's (measured: 2.3 dofs rows numbers in full
  // contact, 13 dofs without) and the implicit integrator's dense dofs by dofs matrices
  // (measured: 13.1 dofs^2 numbers, with or without contact)
  const std::int64_t nv64 = s.dofs;
  s.stack = 3 * nv64 * s.rows + 64 * nv64 + 100000;
  if (options.integrator == MujocoIntegrator::implicit) s.stack += 14 * nv64 * nv64;
  const double nv = s.dofs, nt = s.tendons, nj = s.rows;
  // ten_J and efc_J, efc_JT, efc_AR as doubles with an int column index each, then the
  // arrays linear in the sizes
  s.buffer_bytes =
      12.0 * nt * nv + 24.0 * nj * nv + 12.0 * nj * nj + 1000.0 * (nv + nt + nj + s.contacts);
  s.model_bytes = 1200.0 * n + 300.0 * nt;
  return s;
}

}  // namespace clothbench::reference
