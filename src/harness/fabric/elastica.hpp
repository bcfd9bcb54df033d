#pragma once
/// @file elastica.hpp
/// The heavy inextensible elastica: a strip clamped horizontally at one end and bent by its
/// own weight (the cantilever test of ASTM D1388 and BS 3356), solved by shooting, and its
/// inversion from a measured chord angle to the bending length.
///
/// With s the arc length from the clamp (0 <= s <= l), theta(s) the tangent's angle below the
/// horizontal, M(s) the bending moment, w the weight per length and B the bending rigidity
/// (both per unit width for a fabric: w = areal density x g, B in N m):
///   theta'(s) = M(s) / B,   M'(s) = -w (l - s) cos theta(s),
///   x'(s) = cos theta(s),   y'(s) = sin theta(s)   (y downwards),
///   theta(0) = 0 (clamped level),   M(l) = 0 (free tip).
/// Lengths in units of the bending length c = (B / w)^(1/3) leave one parameter, lambda = l / c:
///   dtheta/dsigma = m,   dm/dsigma = -(lambda - sigma) cos theta,   sigma = s / c, m = M / (w
///   c^2).
/// The shooting parameter is the clamp's moment m(0), found by bisection: too small a moment
/// lets m reach zero before the tip, too large one leaves m > 0 at the tip or bends the strip
/// past the vertical. The equations are integrated by RK4 with fixed steps.

#include <Eigen/Core>

namespace clothbench {

/// How finely the elastica is solved.
struct ElasticaOptions {
  int steps = 2000;  // RK4 steps over the strip's length
};

/// The shape of the strip in units of its bending length c.
struct ElasticaShape {
  double lambda = 0;        // l / c
  double clamp_moment = 0;  // m(0) = M(0) / (w c^2)
  double tip_x = 0;         // x(l) / c, horizontal distance of the tip from the clamp
  double tip_y = 0;         // y(l) / c, drop of the tip below the clamp
  double tip_angle = 0;     // rad, theta(l): the tip's tangent below the horizontal
  /// Chord angle (rad) below the horizontal of the line from the clamp to the tip.
  double chord_angle() const;
};

/// Largest l / c the solver accepts: the chord angle there is 83.9 degrees and the tip hangs
/// within 3e-4 rad of the vertical. Beyond l / c = 7 the hanging part makes the tip's shape
/// exponentially sensitive to the clamp moment: 2000 and 8000 steps disagree by 0.005 degrees
/// at 7.5 and by 0.4 degrees at 9.5, where they agree to 1e-8 degrees at 6.
constexpr double kMaxElasticaLambda = 6.0;

/// Solves the elastica of a strip of length lambda = l / c (0 < lambda <= kMaxElasticaLambda).
/// Throws std::invalid_argument for lambda outside that range or steps < 1.
ElasticaShape solve_elastica(double lambda, const ElasticaOptions& options = {});

/// The solved strip sampled at steps + 1 equally spaced arc lengths, in units of c:
/// 3 by (steps + 1), rows x (along the strip), y (down) and theta (rad).
Eigen::Matrix3Xd elastica_samples(double lambda, const ElasticaOptions& options = {});

/// Chord angle (rad) of a strip of length lambda = l / c.
double elastica_chord_angle(double lambda, const ElasticaOptions& options = {});

/// Tip deflection (m) of a strip of overhang l (m) with bending length c (m): its drop below
/// the clamp.
double elastica_tip_deflection(double l, double c, const ElasticaOptions& options = {});

/// The bending length c (m) at which a strip of overhang l (m) has chord angle theta (rad), by
/// bracketing and bisection on log(l / c) (the chord angle grows monotonically with l / c).
/// Throws std::invalid_argument unless l > 0 and 0 < theta < elastica_chord_angle of
/// kMaxElasticaLambda.
double elastica_bending_length(double l, double theta, const ElasticaOptions& options = {});

/// Peirce's (1930) empirical bending length (m) of a strip of overhang l (m) with chord angle
/// theta (rad): c = l (cos(theta / 2) / (8 tan theta))^(1/3). Throws std::invalid_argument
/// unless 0 < theta < pi / 2.
double peirce_bending_length(double l, double theta);

}  // namespace clothbench
