#include "harness/fabric/cantilever_metrics.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "cloth/model/constants.hpp"
#include "harness/fabric/elastica.hpp"

namespace clothbench {

namespace {

using cloth::kNaN;
using cloth::kPi;

/// Centroid of the current positions of the particles whose rest x is within tol of at.
cloth::Vector3 column_centroid(const cloth::Matrix3X& x0, const cloth::Matrix3X& x,
                               const std::vector<std::uint8_t>* held, double at, double tol,
                               cloth::Vector3* rest) {
  cloth::Vector3 sum = cloth::Vector3::Zero(), rest_sum = cloth::Vector3::Zero();
  int n = 0;
  for (Eigen::Index p = 0; p < x0.cols(); ++p) {
    if (std::abs(x0(0, p) - at) > tol || (held && !(*held)[size_t(p)])) continue;
    sum += x.col(p);
    rest_sum += x0.col(p);
    ++n;
  }
  *rest = rest_sum / n;
  return sum / n;
}

}  // namespace

CantileverMetrics cantilever_metrics(const cloth::Matrix3X& x0,
                                     const std::vector<std::uint8_t>& held,
                                     const cloth::Matrix3X& x, const cloth::Vector3& gravity,
                                     double areal_density, double edge) {
  // the last held column and the tip, by rest x
  double clamp_x = -std::numeric_limits<double>::infinity();
  for (Eigen::Index p = 0; p < x0.cols(); ++p)
    if (held[size_t(p)] && x0(0, p) <= edge) clamp_x = std::max(clamp_x, x0(0, p));
  const double tip_x = x0.row(0).maxCoeff();
  if (!std::isfinite(clamp_x) || !(tip_x > edge))
    throw std::invalid_argument(
        "cantilever: expected held particles at rest x <= edge and particles beyond it");
  const double tol = 1e-9 * std::max(tip_x - x0.row(0).minCoeff(), 1e-300);
  cloth::Vector3 clamp_rest, tip_rest;
  const cloth::Vector3 clamp = column_centroid(x0, x, &held, clamp_x, tol, &clamp_rest);
  const cloth::Vector3 tip = column_centroid(x0, x, nullptr, tip_x, tol, &tip_rest);

  // the chord split along gravity (down) and across it (horizontal)
  CantileverMetrics m;
  const cloth::Vector3 down = gravity.normalized();
  const cloth::Vector3 chord = tip - clamp;
  m.tip_deflection = chord.dot(down);
  m.chord_angle = std::atan2(m.tip_deflection, (chord - m.tip_deflection * down).norm());
  m.overhang = tip_rest.x() - clamp_rest.x();

  // the bending length, where the chord angle is in the elastica's range
  const double top = elastica_chord_angle(kMaxElasticaLambda);
  const bool solvable = m.chord_angle > 0 && m.chord_angle < top;
  m.bending_length = solvable ? elastica_bending_length(m.overhang, m.chord_angle) : kNaN;
  m.bending_length_peirce = m.chord_angle > 0 && m.chord_angle < kPi / 2
                                ? peirce_bending_length(m.overhang, m.chord_angle)
                                : kNaN;
  m.flexural_rigidity = areal_density * gravity.norm() * std::pow(m.bending_length, 3);
  return m;
}

std::vector<TestMetric> cantilever_rows(const CantileverMetrics& m) {
  return {{"chord_angle", m.chord_angle * 180 / kPi, "deg"},
          {"tip_deflection", m.tip_deflection, "m"},
          {"overhang", m.overhang, "m"},
          {"bending_length", m.bending_length, "m"},
          {"bending_length_peirce", m.bending_length_peirce, "m"},
          {"flexural_rigidity", m.flexural_rigidity, "N m"}};
}

}  // namespace clothbench
