#pragma once
/// @file settle.hpp
/// A cloth settled to rest, as the cantilever tests of the hinge model and the fabric presets
/// need it.

#include <catch2/catch.hpp>

#include "cloth/integrators/mass_spring_cloth.hpp"
#include "cloth/model/model.hpp"
#include "cloth/solvers/solver_options.hpp"

namespace clothbench::test {

/// The 3 by #P positions model m settles to: implicit Euler with a line search (LDLT) at
/// 0.02 s steps, whose damping takes the motion out, until after at least 20 steps nothing
/// moves faster than 1e-7 m/s; REQUIREs that 3000 steps suffice. steps, when given, gets the
/// number taken.
inline cloth::Matrix3X settled_positions(const cloth::Model& m, int* steps = nullptr) {
  cloth::SolverOptions o = cloth::line_search_options(cloth::LinearSolver::ldlt);
  o.integrator = cloth::Integrator::implicit_euler;
  o.newton_tolerance = 1e-6;  // m/s^2
  o.newton_iterations = 100;
  cloth::MassSpringCloth cloth(m, o);
  int step = 0;
  for (; step < 3000; ++step) {
    cloth.step(0.02);
    if (step > 20 && cloth.velocities().cwiseAbs().maxCoeff() < 1e-7) break;
  }
  REQUIRE(step < 3000);
  if (steps) *steps = step;
  return cloth.positions();
}

}  // namespace clothbench::test
