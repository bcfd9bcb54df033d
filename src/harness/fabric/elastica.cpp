#include "harness/fabric/elastica.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace clothbench {

namespace {

constexpr double kHalfPi = 1.5707963267948966;

/// The state along the strip, in units of c: angle, moment, position.
struct State {
  double theta = 0, m = 0, x = 0, y = 0;
};

/// Derivative of the state at arc length sigma of a strip of length lambda.
State slope(const State& u, double sigma, double lambda) {
  const double c = std::cos(u.theta);
  return {u.m, -(lambda - sigma) * c, c, std::sin(u.theta)};
}

/// u + h k.
State advance(const State& u, const State& k, double h) {
  return {u.theta + h * k.theta, u.m + h * k.m, u.x + h * k.x, u.y + h * k.y};
}

/// How a shot from the clamp ends.
enum class Shot { under, over };

/// Integrates from the clamp with moment m0 (samples, when given, gets one column per step
/// point) and says whether m0 was too small (the moment changes sign before the tip) or too
/// large (the strip bends past the vertical, or a moment is left at the tip).
Shot shoot(double lambda, double m0, int steps, State& end, Eigen::Matrix3Xd* samples) {
  const double h = lambda / steps;
  State u{0.0, m0, 0.0, 0.0};
  if (samples) samples->col(0) << u.x, u.y, u.theta;
  for (int k = 0; k < steps; ++k) {
    // one RK4 step
    const double s = k * h;
    const State k1 = slope(u, s, lambda);
    const State k2 = slope(advance(u, k1, h / 2), s + h / 2, lambda);
    const State k3 = slope(advance(u, k2, h / 2), s + h / 2, lambda);
    const State k4 = slope(advance(u, k3, h), s + h, lambda);
    u.theta += h / 6 * (k1.theta + 2 * k2.theta + 2 * k3.theta + k4.theta);
    u.m += h / 6 * (k1.m + 2 * k2.m + 2 * k3.m + k4.m);
    u.x += h / 6 * (k1.x + 2 * k2.x + 2 * k3.x + k4.x);
    u.y += h / 6 * (k1.y + 2 * k2.y + 2 * k3.y + k4.y);
    if (samples) samples->col(k + 1) << u.x, u.y, u.theta;
    // the first event decides: a moment gone negative, or an angle past the vertical
    if (u.m < 0) {
      end = u;
      return Shot::under;
    }
    if (u.theta > kHalfPi) {
      end = u;
      return Shot::over;
    }
  }
  end = u;
  return Shot::over;
}

void check(double lambda, const ElasticaOptions& options) {
  if (!(lambda > 0 && lambda <= kMaxElasticaLambda))
    throw std::invalid_argument(
        "elastica: expected 0 < l / c <= " + std::to_string(kMaxElasticaLambda) + ", got " +
        std::to_string(lambda));
  if (options.steps < 1)
    throw std::invalid_argument("elastica: expected steps >= 1, got " +
                                std::to_string(options.steps));
}

/// The clamp moment m(0) of a strip of length lambda, by bisection between 0 (under) and the
/// small-deflection moment lambda^2 / 2 (over: the weight's moment with every cos theta = 1).
double clamp_moment(double lambda, int steps) {
  double lo = 0, hi = lambda * lambda / 2;
  State end;
  while (hi - lo > 4e-16 * hi) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (shoot(lambda, mid, steps, end, nullptr) == Shot::under ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double ElasticaShape::chord_angle() const {
  return std::atan2(tip_y, tip_x);
}

ElasticaShape solve_elastica(double lambda, const ElasticaOptions& options) {
  check(lambda, options);
  ElasticaShape shape;
  shape.lambda = lambda;
  shape.clamp_moment = clamp_moment(lambda, options.steps);
  State end;
  shoot(lambda, shape.clamp_moment, options.steps, end, nullptr);
  shape.tip_x = end.x;
  shape.tip_y = end.y;
  shape.tip_angle = end.theta;
  return shape;
}

Eigen::Matrix3Xd elastica_samples(double lambda, const ElasticaOptions& options) {
  check(lambda, options);
  Eigen::Matrix3Xd samples(3, options.steps + 1);
  State end;
  shoot(lambda, clamp_moment(lambda, options.steps), options.steps, end, &samples);
  return samples;
}

double elastica_chord_angle(double lambda, const ElasticaOptions& options) {
  return solve_elastica(lambda, options).chord_angle();
}

double elastica_tip_deflection(double l, double c, const ElasticaOptions& options) {
  if (!(l > 0 && c > 0)) throw std::invalid_argument("elastica: expected l > 0 and c > 0");
  return c * solve_elastica(l / c, options).tip_y;
}

double elastica_bending_length(double l, double theta, const ElasticaOptions& options) {
  const double top = elastica_chord_angle(kMaxElasticaLambda, options);
  if (!(l > 0 && theta > 0 && theta < top))
    throw std::invalid_argument("elastica: expected l > 0 and a chord angle in (0, " +
                                std::to_string(top) + ") rad, got l = " + std::to_string(l) +
                                ", theta = " + std::to_string(theta));
  // bracket log(lambda) around the small-deflection guess tan theta = lambda^3 / 8
  const double guess = std::min(std::cbrt(8 * std::tan(theta)), kMaxElasticaLambda);
  auto f = [&](double log_lambda) {
    return elastica_chord_angle(std::min(std::exp(log_lambda), kMaxElasticaLambda), options) -
           theta;
  };
  double a = std::log(guess), b = a;
  double fa = f(a), fb = fa;
  const double step = std::log(1.5);
  while (fa > 0) fa = f(a -= step);
  while (fb <= 0) b = std::min(b + step, std::log(kMaxElasticaLambda)), fb = f(b);
  // Illinois false position: the bracket shrinks from both sides
  int side = 0;
  for (int k = 0; k < 200 && b - a > 1e-14; ++k) {
    const double x = (a * fb - b * fa) / (fb - fa);
    const double fx = f(x);
    if (std::abs(fx) <= 1e-14) return l / std::min(std::exp(x), kMaxElasticaLambda);
    if ((fx > 0) == (fb > 0)) {
      b = x, fb = fx;
      if (side == -1) fa /= 2;
      side = -1;
    } else {
      a = x, fa = fx;
      if (side == 1) fb /= 2;
      side = 1;
    }
  }
  return l / std::min(std::exp(0.5 * (a + b)), kMaxElasticaLambda);
}

double peirce_bending_length(double l, double theta) {
  if (!(theta > 0 && theta < kHalfPi))
    throw std::invalid_argument("Peirce's bending length: expected 0 < theta < pi / 2 rad");
  return l * std::cbrt(std::cos(theta / 2) / (8 * std::tan(theta)));
}

}  // namespace clothbench
