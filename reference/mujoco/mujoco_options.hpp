#pragma once
/// @file mujoco_options.hpp
/// Options of the mujoco engine: MuJoCo 2.2.2's time integrator and the contact parameters
/// (what the engine cannot model is mujoco_refusal.hpp).

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace clothbench::reference {

/// MuJoCo 2.2.2's integrators (mjtIntegrator).
enum class MujocoIntegrator {
  euler,    ///< semi-implicit Euler: v += h a(x, v), then x += h v; implicit in joint damping
            ///< only, which this model has none of (spring damping lives in the tendons)
  rk4,      ///< classic fourth-order Runge-Kutta
  implicit  ///< implicit in velocity: (M - h D) dv = h F, D the tendon damping's velocity
            ///< derivative within each particle's own dofs only (2.2.2 keeps D in M's
            ///< sparsity, and every particle is its own body: the -c n n^T coupling between
            ///< a spring's two ends is dropped); the spring stiffness stays explicit
};

/// "euler", "rk4" or "implicit".
const char* mujoco_integrator_name(MujocoIntegrator i);
/// The integrator with that name, if any.
std::optional<MujocoIntegrator> parse_mujoco_integrator(const std::string& name);
/// Every integrator, in the order above.
const std::vector<MujocoIntegrator>& all_mujoco_integrators();

/// Options of the mujoco engine. Unset contact keys take the scene's values.
struct MujocoOptions {
  MujocoIntegrator integrator = MujocoIntegrator::euler;
  std::optional<double> margin;    // m, contact shell of every collider; unset: each its own
  std::optional<double> friction;  // Coulomb coefficient of every collider; unset: each its own
  std::array<double, 2> solref = {0.02, 1.0};  // MuJoCo's default: time constant (s), damping
                                               // ratio of the contact's soft constraint
  std::array<double, 3> solimp = {0.9, 0.95, 0.001};  // MuJoCo's default: impedance at zero
                                                      // and at full penetration, width (m)
  bool elliptic = false;  // elliptic friction cone instead of MuJoCo's default pyramidal one
};

}  // namespace clothbench::reference
