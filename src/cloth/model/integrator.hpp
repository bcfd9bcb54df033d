#pragma once
/// @file integrator.hpp
/// The time integrators of the custom engine and their names (used in scenario files and CSV).

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cloth {

/// One name each, used everywhere.
enum class Integrator {
  explicit_euler,    ///< x += h v, v += h a, both from the old state
  symplectic_euler,  ///< v += h a, then x += h v
  picard_implicit,   ///< the report's "implicit Euler": one fixed-point pass from a predictor
  midpoint,          ///< explicit midpoint (RK2)
  rk4,               ///< classic fourth-order Runge-Kutta
  implicit_euler,    ///< backward Euler, Newton-linearised, filtered conjugate gradient
  imex_euler,        ///< Bullet's deformable explicit scheme: springs and gravity explicit,
                     ///< x += h v, spring dampers implicit (one linear solve per step)
  xpbd,              ///< extended position-based dynamics on the springs (xpbd.hpp)
  projective         ///< fast mass-springs: local/global backward Euler (projective.hpp)
};

/// "explicit-euler", "symplectic-euler", "picard-implicit", "midpoint", "rk4", "implicit-euler",
/// "imex-euler", "xpbd", "projective".
const char* integrator_name(Integrator i);
/// The integrator with that name, if any.
std::optional<Integrator> parse_integrator(std::string_view name);
/// Every integrator, in the order above.
const std::vector<Integrator>& all_integrators();
/// Force evaluations per step of the explicit methods (implicit-euler: per Newton iteration;
/// imex-euler: the elastic forces once, its damping solve counted in CG iterations; xpbd: per
/// substep and iteration, one sweep over the springs; projective: per iteration).
int force_evals_per_step(Integrator i);
/// Order of accuracy of the method.
int integrator_order(Integrator i);

}  // namespace cloth
