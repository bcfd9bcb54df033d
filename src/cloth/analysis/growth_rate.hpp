#pragma once
/// @file growth_rate.hpp
/// How fast a small perturbation of a state grows under an engine's step map, measured black
/// box: set the state, step, read the state (Simulator::set_state).
///
/// The map Phi takes a state s = (x, v) at time t through `steps` steps of dt. Its Jacobian J
/// at s is applied to a vector q by a finite difference, J q ~ (Phi(s + e q) - Phi(s)) / e,
/// in scaled coordinates (positions over a length, velocities over a speed, both set by the
/// state) so that one relative perturbation size suits both halves. Arnoldi's method (a
/// Krylov space built one product at a time, its Hessenberg matrix's eigenvalues as Ritz
/// values) finds the outermost eigenvalues of J, complex pairs included; rho is the largest
/// modulus, the amplification of the fastest-growing mode over the map's steps * dt. Only the
/// free axes (Model::free) are perturbed; held axes stay as the state has them.
///
/// Why not block (subspace) iteration: a flat or slack cloth has many free bending modes
/// whose block of J is non-normal (x' = v, v' = 0: a Jordan block at 1), and Ritz values from
/// a few vectors then sit above every true eigenvalue and settle there (measured on a 5 x 5
/// rest grid: rho 1.03 "converged" where J's is 1, and explicit Euler's nearly equal top
/// eigenvalues unconverged after 300 iterations). Arnoldi with the Ritz pair's residual as
/// the stopping test resolves both (tests/cloth/test_growth_rate.cpp).
///
/// A map that is not differentiable at s (a contact switching on or off, stick turning to
/// slip, an iteration stopping at a different count) gives difference quotients that depend
/// on e and on its sign: the estimate compares the forward and backward differences on the
/// dominant mode's direction and reports the state as non-smooth when they disagree, or when
/// the engine's collider contact count differs between the base map and the maps perturbed
/// along the mode (contacts that flip elsewhere, under the Krylov vectors' perturbation of
/// every particle, do not make the mode's growth ill-defined).

#include <complex>
#include <limits>
#include <string>

#include "cloth/model/simulator.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// A state of the step map.
struct MapState {
  Matrix3X x;    // 3 by #P positions (m)
  Matrix3X v;    // 3 by #P velocities (m/s)
  double t = 0;  // s
};

/// Smallest relative perturbation accepted: below it, round-off in the stepped state is as
/// large as the difference it is to measure.
constexpr double kMinPerturbation = 1e-12;

/// Largest relative perturbation accepted: above it a perturbation is no longer small (at
/// 1e-3 of the bounding box's diagonal the particles of a 100 x 100 cloth move by a seventh of
/// their spacing), and the differences measure the nonlinear map, not its linearisation.
constexpr double kMaxPerturbation = 1e-3;

/// Options of one growth estimate.
struct GrowthOptions {
  double perturbation = 1e-7;   // finite-difference size, relative to the state's scale
  int max_iterations = 120;     // Krylov steps (forward differences) at most
  double rel_tol = 1e-7;        // stop when the dominant Ritz pair's residual |J y - theta y|
                                // is below this times |theta| (|y| = 1)
  double nonsmooth_tol = 0.05;  // forward and backward differences disagreeing by more than
                                // this (relative) call the state non-smooth
  // a caller that needs only which side of a threshold rho is on (see decided_side):
  double decide_below = 0;  // > 0: stop once rho is decided below this
  double decide_above = std::numeric_limits<double>::infinity();  // finite: stop once rho is
                                                                  // decided above this
  int decide_checks = 2;          // consecutive convergence checks that must agree
  double decide_residual = 1e-2;  // and the relative residual at most this (with 2 checks: no
                                  // wrong side over 458 estimates of the seed and flag
                                  // searches, docs/methods.md)
};

/// What one estimate found.
struct GrowthEstimate {
  double rho = std::numeric_limits<double>::quiet_NaN();   // largest |eigenvalue| of J
  double rate = std::numeric_limits<double>::quiet_NaN();  // 1/s, ln(rho) / (steps dt)
  std::complex<double> eigenvalue;                         // the dominant eigenvalue of J
  bool smooth = true;            // false: the map is not differentiable at the state
  std::string nonsmooth_reason;  // why not, in words without commas (CSV)
  Matrix3X mode;                 // 3 by #P position part of the dominant mode (real part,
                                 // largest entry 1 in modulus; 0 on held axes)
  Matrix3X mode_velocity;        // 3 by #P velocity part, scaled alike
  /// |J y - theta y| of the dominant Ritz pair (|y| = 1) when the estimate stopped (NaN: no
  /// Krylov step made)
  double residual = std::numeric_limits<double>::quiet_NaN();
  int iterations = 0;      // Krylov steps made
  int products = 0;        // maps evaluated (each `steps` steps of the engine)
  bool converged = false;  // the residual met rel_tol within max_iterations
  int decided = 0;         // -1: stopped early, rho decided below decide_below; +1: above
                           // decide_above; 0: ran to rel_tol or max_iterations
};

/// Which side of the thresholds the dominant Ritz value theta (residual |J y - theta y| with
/// |y| = 1) is on, allowing for its error: -1 when |theta| + sqrt(residual) < below, +1 when
/// |theta| - sqrt(residual) > above, else 0. The square root, not the residual itself (which
/// bounds the error for a normal J only), because a Ritz value of a 2 by 2 Jordan block with
/// coupling c, J's block for a free bending mode (x' = v: c = 1 in the scaled coordinates), is
/// off by about sqrt(c residual).
int decided_side(std::complex<double> theta, double residual, double below, double above);

/// Estimates the growth of perturbations of state s under `steps` steps of dt of sim, whose
/// free axes are free (3 by #P, 1 where the axis moves). sim is left in an unspecified state.
/// Throws std::invalid_argument for a perturbation below kMinPerturbation, steps < 1,
/// dt <= 0, no free axis or shapes that do not match, and std::logic_error when sim cannot
/// set its state. A map that overflows (a state that is not finite after the steps) gives rho
/// and rate infinite and converged false. Costs iterations + 3 products: the base map, one
/// per Krylov step, and a forward and a backward difference for the smoothness check. With
/// decide_below or decide_above set, stops as soon as decided_side has given the same nonzero
/// side at decide_checks consecutive checks with the relative residual at most
/// decide_residual (GrowthEstimate::decided); rho is then only that precise.
GrowthEstimate estimate_growth(Simulator& sim, const MapState& s, double dt, int steps,
                               const Matrix3X& free, const GrowthOptions& o = {});

}  // namespace cloth
