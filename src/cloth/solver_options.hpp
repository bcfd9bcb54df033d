#pragma once
/// @file solver_options.hpp
/// Options of the custom engine: which integrator and how implicit Euler solves.

#include "cloth/integrator.hpp"

namespace cloth {

/// Options of the custom engine.
struct SolverOptions {
  Integrator integrator = Integrator::rk4;
  int newton_iterations = 1;     // implicit-euler: 1 is Baraff and Witkin's single linear solve
  double cg_tolerance = 1e-8;    // implicit-euler: relative residual |S r| / |S b|
  int cg_max_iterations = 2000;  // implicit-euler
  bool clamp_compressed = true;  // implicit-euler: drop negative transverse stiffness
};

}  // namespace cloth
