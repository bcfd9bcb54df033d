// The joint solver of clothbench fit on analytic coupled functions: Gauss-Newton in ln p is
// exact on power laws (one step after the differences), it converges on a coupled function that
// is not a power law, gives the least-squares compromise of targets that conflict, stops at the
// end of a range, and steps around a region that gives no metric (a blow-up).

#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "harness/sweeps/fit_joint.hpp"

using namespace clothbench;

namespace {

/// Options for the targets with relative tolerance tol, from start, in [lo, hi] for both.
JointFitOptions aim(const Eigen::Vector2d& target, const Eigen::Vector2d& start, double tol = 0.03,
                    double lo = 1e-4, double hi = 1e4) {
  JointFitOptions o;
  o.target = target;
  o.tolerance = tol * target.cwiseAbs();
  o.start = start;
  o.lo = Eigen::Vector2d::Constant(lo);
  o.hi = Eigen::Vector2d::Constant(hi);
  o.names = {"p", "q"};
  return o;
}

/// m1 = 0.02 p^0.3 q^0.1, m2 = 5 p^-0.2 q^0.5: a bending length and a stiffness that each
/// lean on the other's parameter.
Eigen::VectorXd coupled_power(const Eigen::VectorXd& p) {
  return Eigen::Vector2d(0.02 * std::pow(p[0], 0.3) * std::pow(p[1], 0.1),
                         5.0 * std::pow(p[0], -0.2) * std::pow(p[1], 0.5));
}

/// Every metric within its tolerance.
bool within(const JointFitResult& r, const JointFitOptions& o) {
  return ((r.metrics - o.target).array().abs() <= o.tolerance.array()).all();
}

}  // namespace

TEST_CASE("the joint fit solves coupled power laws in one step after the differences", "[fit]") {
  const Eigen::Vector2d truth(300.0, 2000.0);
  const Eigen::Vector2d start = GENERATE(Eigen::Vector2d(1000.0, 500.0), Eigen::Vector2d(1.0, 1.0));
  const JointFitOptions o = aim(coupled_power(truth), start);
  const JointFitResult r = solve_joint(coupled_power, o);
  CAPTURE(r.note, r.samples.size(), r.parameters.transpose());
  REQUIRE(r.status == FitStatus::converged);
  REQUIRE(within(r, o));
  REQUIRE(r.metrics == coupled_power(r.parameters));
  // in ln p against ln m the laws are linear: differences give the exact Jacobian and the
  // first (barely damped) step lands on the truth, unless the step cap (10x) splits it
  const double decades = (truth.array() / start.array()).log().abs().maxCoeff() / o.max_step;
  REQUIRE(int(r.samples.size()) <= 3 + int(std::ceil(decades)));
  REQUIRE(((r.parameters - truth).array() / truth.array()).abs().maxCoeff() < 0.01);
  // the sensitivities, against the laws' derivatives at the fitted parameters
  const Eigen::Vector2d p = r.parameters, m = coupled_power(p);
  REQUIRE(r.sensitivity(0, 0) == Approx(0.3 * m[0] / p[0]).epsilon(0.02));
  REQUIRE(r.sensitivity(0, 1) == Approx(0.1 * m[0] / p[1]).epsilon(0.02));
  REQUIRE(r.sensitivity(1, 0) == Approx(-0.2 * m[1] / p[0]).epsilon(0.02));
  REQUIRE(r.sensitivity(1, 1) == Approx(0.5 * m[1] / p[1]).epsilon(0.02));
}

TEST_CASE("the joint fit converges on a coupled function that is not a power law", "[fit]") {
  // m1 = p + q / 2, m2 = p q^2; (2, 3) gives (3.5, 18) (so does (0.5, 6): either will do)
  const auto f = [](const Eigen::VectorXd& p) {
    return Eigen::VectorXd(Eigen::Vector2d(p[0] + 0.5 * p[1], p[0] * p[1] * p[1]));
  };
  const JointFitOptions o = aim(Eigen::Vector2d(3.5, 18.0), Eigen::Vector2d(20.0, 0.5), 0.01);
  const JointFitResult r = solve_joint(f, o);
  CAPTURE(r.note, r.samples.size(), r.parameters.transpose());
  REQUIRE(r.status == FitStatus::converged);
  REQUIRE(within(r, o));
  REQUIRE(r.metrics == f(r.parameters));
  REQUIRE(r.samples.size() <= 16);
}

TEST_CASE("the joint fit gives the least-squares compromise of conflicting targets", "[fit]") {
  // m1 = p q and m2 = 2 p q cannot be 1 and 3 at once; in units of 3 % of each (ln m), the
  // least squares put ln(p q) half way: p q = sqrt(1.5), m2 / m1 = 2 whatever p and q are
  const auto f = [](const Eigen::VectorXd& p) {
    return Eigen::VectorXd(Eigen::Vector2d(p[0] * p[1], 2.0 * p[0] * p[1]));
  };
  const JointFitOptions o = aim(Eigen::Vector2d(1.0, 3.0), Eigen::Vector2d(10.0, 10.0));
  const JointFitResult r = solve_joint(f, o);
  CAPTURE(r.note, r.samples.size(), r.parameters.transpose());
  REQUIRE(r.status == FitStatus::unreachable);
  REQUIRE_FALSE(within(r, o));
  REQUIRE(r.metrics[0] == Approx(std::sqrt(1.5)).epsilon(0.01));
  REQUIRE(r.note.find("least-squares") != std::string::npos);
  REQUIRE(r.samples.size() <= 12);
}

TEST_CASE("the joint fit stops at the end of a parameter's range", "[fit]") {
  // m = (p, q) with q's target past its range: p is met, q ends at the top
  const auto f = [](const Eigen::VectorXd& p) { return p; };
  JointFitOptions o = aim(Eigen::Vector2d(10.0, 50.0), Eigen::Vector2d(1.0, 1.0));
  o.hi << 100.0, 20.0;
  const JointFitResult r = solve_joint(f, o);
  CAPTURE(r.note, r.samples.size(), r.parameters.transpose());
  REQUIRE(r.status == FitStatus::unreachable);
  REQUIRE(r.parameters[1] == 20.0);
  REQUIRE(std::abs(r.metrics[0] - 10.0) <= o.tolerance[0]);
  REQUIRE(r.note.find("top of q's range") != std::string::npos);
}

TEST_CASE("the joint fit steps around parameters that give no metric", "[fit]") {
  // no metric for p > 7 (a blow-up); the start's forward difference lands there
  const auto f = [](const Eigen::VectorXd& p) {
    if (p[0] > 7.0) return Eigen::VectorXd(Eigen::Vector2d::Constant(NAN));
    return Eigen::VectorXd(
        Eigen::Vector2d(std::sqrt(p[0]) * std::pow(p[1], 0.2), p[1] / std::pow(p[0], 0.3)));
  };
  const Eigen::Vector2d truth(5.0, 2.0);
  const JointFitOptions o = aim(f(truth), Eigen::Vector2d(6.9, 0.2));
  const JointFitResult r = solve_joint(f, o);
  CAPTURE(r.note, r.samples.size(), r.parameters.transpose());
  REQUIRE(r.status == FitStatus::converged);
  REQUIRE(within(r, o));
  REQUIRE(r.parameters[0] <= 7.0);
  bool blew_up = false;
  for (const JointSample& s : r.samples) blew_up = blew_up || !s.metrics.allFinite();
  REQUIRE(blew_up);
  REQUIRE(r.samples.size() <= 12);
}

TEST_CASE("the joint fit says when the start gives no metric, and refuses bad options", "[fit]") {
  const auto none = [](const Eigen::VectorXd&) {
    return Eigen::VectorXd(Eigen::Vector2d::Constant(NAN));
  };
  const JointFitOptions o = aim(Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(1.0, 1.0));
  const JointFitResult r = solve_joint(none, o);
  REQUIRE(r.status == FitStatus::failed);
  REQUIRE(r.samples.size() == 1);
  JointFitOptions bad = o;
  bad.lo[0] = 0.0;
  REQUIRE_THROWS_AS(solve_joint(coupled_power, bad), std::invalid_argument);
  bad = o;
  bad.hi = Eigen::Vector3d::Ones();
  REQUIRE_THROWS_AS(solve_joint(coupled_power, bad), std::invalid_argument);
}
