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
/// That case is exact, and the limit is checked on every omega in [0, omega_max] (Lanczos).
///
/// Otherwise (say softer bend springs with the same damper) the modes of K do not diagonalise
/// D and each has its own damping. Up to kDenseModalDofs free DOFs the modes are then found
/// densely: the top modes (the upper third, at least 200) are solved coupled through D
/// (the quadratic eigenproblem lambda^2 - lambda M^-1 D - M^-1 K = 0 in their span), and each
/// eigenvalue pair becomes the damped oscillator with those roots; the lower modes keep their
/// own Rayleigh damping phi^T D phi. The limits of the methods whose step is a polynomial
/// (or rational) function of h lambda are then those of the linearisation up to the
/// truncation of the coupling. Symplectic Euler's step matrix is not a function of lambda
/// alone: its eigenvalues are 1 + h s with s^2 - s (M^-1 D + h M^-1 K) - M^-1 K = 0, solved
/// at each h for the top kSymplecticCoupled modes coupled. Above kDenseModalDofs beta is
/// taken from the Rayleigh quotient of D on the top mode for every omega in [0, omega_max].
/// LinearSpectrum::exact and ::method say which was done.

#include <complex>
#include <string>
#include <vector>

#include "cloth/model/integrator.hpp"
#include "cloth/model/model.hpp"

namespace cloth {

/// Free DOFs up to which non-proportional damping is analysed densely (a dense symmetric
/// eigenproblem of this size takes a few seconds).
constexpr int kDenseModalDofs = 2000;

/// Top modes solved coupled at each h for symplectic Euler (a 2 x this eigenproblem per h).
constexpr int kSymplecticCoupled = 120;

/// One damped mode q'' + a q' + omega^2 q = 0 of the linearised scene.
struct DampedMode {
  double omega = 0;  // rad/s, undamped frequency (|lambda|^2 = omega^2 for its roots)
  double a = 0;      // 1/s, damping rate (the roots sum to -a)
};

/// The spectrum facts the limits depend on.
struct LinearSpectrum {
  double omega_max = 0;           // rad/s, highest undamped frequency of the free DOFs
  double beta = 0;                // s, modal damping per omega^2 (c / k when exact; the top mode's
                                  // Rayleigh quotient otherwise)
  double gamma = 0;               // 1/s, uniform damping from air drag
  bool exact = true;              // false: damping not proportional to stiffness (see method)
  std::string method;             // how the modes were found, in words without commas (CSV)
  std::vector<DampedMode> modes;  // non-empty: the modes the limits are checked on (dense
                                  // analysis); empty: every omega in [0, omega_max] with beta
  // dense analysis, for symplectic Euler (whose step is not a function of lambda alone): the
  // top #C modes solved coupled at each h, and the modes below them with their own damping
  Eigen::VectorXd coupled_omega2;     // #C squared frequencies (rad^2/s^2), ascending
  Eigen::MatrixXd coupled_damping;    // #C by #C, Phi^T M^-1/2 D M^-1/2 Phi (1/s, negative)
  std::vector<DampedMode> uncoupled;  // the other modes
  int lanczos_steps = 0;
};

/// The modes of the free DOFs at the rest state (see the file comment): omega_max by Lanczos
/// with full reorthogonalisation (deterministic start vector), and with damping not
/// proportional to stiffness the dense modal analysis up to dense_max_dofs free DOFs.
LinearSpectrum linear_spectrum(const Model& model, int max_steps = 200,
                               int dense_max_dofs = kDenseModalDofs);

/// True when one step of size h of integrator i is stable (spectral radius <= 1) for the
/// mode q'' + (beta omega^2 + gamma) q' + omega^2 q = 0.
bool mode_stable(Integrator i, double h, double omega, double beta, double gamma);

/// Spectral radius of one step of size h of integrator i on that mode.
double mode_radius(Integrator i, double h, double omega, double beta, double gamma);

/// Largest h for which every mode is stable (s.modes, or every omega in [0, omega_max] with
/// beta and gamma); infinity for implicit-euler. The stable set need not be an interval: this
/// is the first failure.
double predicted_stable_dt(Integrator i, const LinearSpectrum& s);

/// The mode that fails first just above the predicted limit, in words
/// ("omega 566 rad/s (overdamped)" or "omega 120 rad/s (oscillatory)"); no commas (CSV).
std::string limiting_mode(Integrator i, const LinearSpectrum& s);

/// The same, given h = predicted_stable_dt(i, s) (which takes a while with coupled modes).
std::string limiting_mode(Integrator i, const LinearSpectrum& s, double h);

}  // namespace cloth
