#pragma once
/// @file xpbd.hpp
/// Extended position-based dynamics (Macklin, Mueller and Chentanez 2016) on the cloth's
/// springs: each spring is a distance constraint C = |x_b - x_a| - l0 with compliance
/// alpha = 1 / k, and its damper the paper's dissipation term with beta = c. A step of h is
/// `substeps` substeps of h / substeps (Macklin et al. 2019's "small steps" with substeps > 1
/// and iterations = 1); each predicts positions from gravity (air drag implicit), then runs
/// `iterations` Gauss-Seidel sweeps over every spring, and takes the velocity from the
/// position change. A held axis has zero inverse mass on that axis only.
///
/// What it converges to: with the multipliers converged (many sweeps) each substep is a
/// backward-Euler-like step of the compliant constraints, whose statics are the springs' (a
/// hanging chain's stretch is m g / k per particle carried, to round-off from 32 sweeps on
/// the test chain). At a fixed sweep count and a large step (k h^2 / m above 1) an unconverged
/// sweep leaves part of every constraint unsolved, so the result depends on the sweep count;
/// as h shrinks a sweep's contraction factor k h^2 / (m + k h^2) goes to 0 and the method
/// converges at first order to the spring ODE's solution (README, the flag). With one sweep
/// per substep the damping term's share of each projection puts the statics off by
/// O(c h_s / m), first order in the substep (tests/cloth/test_methods.cpp).

#include "cloth/model/model.hpp"
#include "cloth/model/simulator.hpp"
#include "cloth/model/types.hpp"
#include "cloth/solvers/solver_options.hpp"

namespace cloth {

/// One XPBD step of h seconds on x and v (each 3 by #P); returns the energy the spring
/// dampers and air drag took out (J), measured from each substep's end velocities.
/// @param p       3 by #P scratch (the predicted positions)
/// @param lambda  scratch for the springs' multipliers, sized on first use
double xpbd_step(const Model& m, const SolverOptions& o, double h, Matrix3X& x, Matrix3X& v,
                 Matrix3X& p, VectorX& lambda, Counters& counters);

}  // namespace cloth
