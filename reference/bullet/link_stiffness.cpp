#include "reference/bullet/link_stiffness.hpp"

#include <cmath>
#include <limits>

namespace clothbench::reference {

double projected_link_stiffness(double klst, double inv_mass_sum, double dt, int iterations) {
  const double s = 1.0 - std::pow(1.0 - klst, iterations);
  if (s >= 1.0) return std::numeric_limits<double>::infinity();
  return s / ((1.0 - s) * inv_mass_sum * dt * dt);
}

double matched_link_klst(double k, double inv_mass_sum, double dt, int iterations) {
  // (1 - kLST)^n = 1 - s = 1 / (1 + k w dt^2); expm1/log1p keep soft links accurate
  const double a = k * inv_mass_sum * dt * dt;
  return -std::expm1(-std::log1p(a) / iterations);
}

}  // namespace clothbench::reference
