#pragma once
/// @file linear_stability.hpp
/// The time-step limit each integrator has on a scene, from linear theory.
///
/// Linearised at its initial (rest) state, the free degrees of freedom obey
///   M x'' = K x + D x',   K = df/dx, D = df/dv (springs and air drag).
/// At rest every spring has b = 0, so K = sum_k k_kind G_kind and D = c G - drag I with the
/// same geometric blocks G: when all spring kinds share one stiffness, D = (c / k) K - drag I
/// and every mode of M^-1 K (eigenvalue -omega^2) is a damped oscillator
///   q'' + (beta omega^2 + gamma) q' + omega^2 q = 0,   beta = c / k, gamma = drag / m.
/// That case is exact. Otherwise beta is taken from the Rayleigh quotient of D on the top mode
/// (an approximation, said so in LinearSpectrum::exact).

#include <complex>
#include <string>

#include "cloth/integrator.hpp"
#include "cloth/model.hpp"

namespace cloth {

/// The spectrum facts the limits depend on.
struct LinearSpectrum {
  double omega_max = 0;  // rad/s, highest undamped frequency of the free DOFs
  double omega_min = 0;  // rad/s, lowest (Lanczos estimate)
  double beta = 0;       // s, modal damping per omega^2 (c / k when exact)
  double gamma = 0;      // 1/s, uniform damping from air drag
  bool exact = true;     // false: damping not proportional to stiffness (beta approximated)
  int lanczos_steps = 0;
};

/// Extreme eigenvalues of M^-1 K on the free DOFs at the rest state, by Lanczos with full
/// reorthogonalisation (deterministic start vector).
LinearSpectrum linear_spectrum(const Model& model, int max_steps = 200);

/// True when one step of size h of integrator i is stable (spectral radius <= 1) for the
/// mode q'' + (beta omega^2 + gamma) q' + omega^2 q = 0.
bool mode_stable(Integrator i, double h, double omega, double beta, double gamma);

/// Spectral radius of one step of size h of integrator i on that mode.
double mode_radius(Integrator i, double h, double omega, double beta, double gamma);

/// Largest h for which every mode with omega in [0, omega_max] is stable; infinity for
/// implicit-euler. The stable set need not be an interval: this is the first failure.
double predicted_stable_dt(Integrator i, const LinearSpectrum& s);

/// The mode that fails first just above the predicted limit, in words
/// ("omega 566 rad/s (overdamped)" or "omega 120 rad/s (oscillatory)"); no commas (CSV).
std::string limiting_mode(Integrator i, const LinearSpectrum& s);

}  // namespace cloth
