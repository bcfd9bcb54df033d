#pragma once
/// @file link_stiffness.hpp
/// The spring constant a position-projected link of Bullet's classic soft body behaves like.
///
/// One projection pass of a link with stiffness kLST removes the fraction kLST of its stretch,
/// so n Gauss-Seidel passes of an isolated link remove s = 1 - (1 - kLST)^n of it. At rest
/// under a load, each step adds the stretch F w dt^2 (w: summed inverse masses of the link's
/// two nodes) and the passes remove s of the total, so the stretch e settles where
/// e = (1 - s) (e + F w dt^2): the link acts like a spring of constant
///   k_eff = s / ((1 - s) w dt^2).
/// Pure arithmetic, no Bullet: the tests and the softbody adapter share it.

namespace clothbench::reference {

/// Spring constant (N/m) of an isolated projected link.
/// @param klst           Bullet's link stiffness kLST, in (0, 1]
/// @param inv_mass_sum   w, summed inverse masses of the two nodes (1/kg), > 0
/// @param dt             time step (s), > 0
/// @param iterations     position-solver passes per step (Bullet's piterations), >= 1
/// @return k_eff (N/m); infinite for klst = 1
double projected_link_stiffness(double klst, double inv_mass_sum, double dt, int iterations);

/// The kLST whose isolated projected link acts like a spring of constant k: the inverse of
/// projected_link_stiffness, kLST = 1 - (1 + k w dt^2)^(-1/n).
/// @param k              target spring constant (N/m), > 0
/// @param inv_mass_sum   w (1/kg), > 0
/// @param dt             time step (s), > 0
/// @param iterations     position-solver passes per step, >= 1
/// @return kLST in (0, 1)
double matched_link_klst(double k, double inv_mass_sum, double dt, int iterations);

}  // namespace clothbench::reference
