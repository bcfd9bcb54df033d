#include "cloth/model/integrator.hpp"

namespace cloth {

const char* integrator_name(Integrator i) {
  switch (i) {
    case Integrator::explicit_euler:
      return "explicit-euler";
    case Integrator::symplectic_euler:
      return "symplectic-euler";
    case Integrator::picard_implicit:
      return "picard-implicit";
    case Integrator::midpoint:
      return "midpoint";
    case Integrator::rk4:
      return "rk4";
    case Integrator::implicit_euler:
      return "implicit-euler";
    case Integrator::imex_euler:
      return "imex-euler";
    case Integrator::xpbd:
      return "xpbd";
    case Integrator::projective:
      return "projective";
  }
  return "?";
}

const std::vector<Integrator>& all_integrators() {
  static const std::vector<Integrator> all = {Integrator::explicit_euler,
                                              Integrator::symplectic_euler,
                                              Integrator::picard_implicit,
                                              Integrator::midpoint,
                                              Integrator::rk4,
                                              Integrator::implicit_euler,
                                              Integrator::imex_euler,
                                              Integrator::xpbd,
                                              Integrator::projective};
  return all;
}

std::optional<Integrator> parse_integrator(std::string_view name) {
  for (Integrator i : all_integrators())
    if (name == integrator_name(i)) return i;
  return std::nullopt;
}

int force_evals_per_step(Integrator i) {
  switch (i) {
    case Integrator::explicit_euler:
    case Integrator::symplectic_euler:
    case Integrator::implicit_euler:
    case Integrator::imex_euler:
    case Integrator::xpbd:
    case Integrator::projective:
      return 1;
    case Integrator::picard_implicit:
    case Integrator::midpoint:
      return 2;
    case Integrator::rk4:
      return 4;
  }
  return 0;
}

int integrator_order(Integrator i) {
  switch (i) {
    case Integrator::midpoint:
      return 2;
    case Integrator::rk4:
      return 4;
    default:
      return 1;
  }
}

}  // namespace cloth
