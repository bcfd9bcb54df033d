#include "reference/mujoco/mujoco_options.hpp"

namespace clothbench::reference {

const char* mujoco_integrator_name(MujocoIntegrator i) {
  switch (i) {
    case MujocoIntegrator::euler:
      return "euler";
    case MujocoIntegrator::rk4:
      return "rk4";
    case MujocoIntegrator::implicit:
      return "implicit";
  }
  return "?";
}

const std::vector<MujocoIntegrator>& all_mujoco_integrators() {
  static const std::vector<MujocoIntegrator> all = {MujocoIntegrator::euler, MujocoIntegrator::rk4,
                                                    MujocoIntegrator::implicit};
  return all;
}

std::optional<MujocoIntegrator> parse_mujoco_integrator(const std::string& name) {
  for (MujocoIntegrator i : all_mujoco_integrators())
    if (name == mujoco_integrator_name(i)) return i;
  return std::nullopt;
}

}  // namespace clothbench::reference
