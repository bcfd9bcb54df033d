#pragma once
/// @file cantilever_metrics.hpp
/// The cantilever test's metrics (ASTM D1388 option A, fixed overhang) measured on a settled
/// strip: its chord angle, tip deflection, and the bending length and flexural rigidity they
/// give through the heavy elastica (elastica.hpp) and through Peirce's formula.

#include <cstdint>
#include <string>
#include <vector>

#include "cloth/model/types.hpp"
#include "harness/fabric/test_metric.hpp"

namespace clothbench {

/// What a cantilever's shape says about its fabric. NaN where a metric is undefined (a chord
/// angle outside the elastica's range: a strip that rises, or a chord steeper than 83.9
/// degrees).
struct CantileverMetrics {
  double overhang = 0;               // m, l: rest length along x from the clamp to the tip
  double chord_angle = 0;            // rad, below the horizontal, clamp to tip
  double tip_deflection = 0;         // m, the tip's drop below the clamp
  double bending_length = 0;         // m, c of the elastica with this chord angle at l
  double bending_length_peirce = 0;  // m, Peirce's c
  double flexural_rigidity = 0;      // N m, areal weight x c^3 (the elastica's c)
};

/// Measures a cantilever. The clamp is the centroid of the held particles (held[p] != 0) with
/// the largest rest x at or below edge (the last held column), the tip the centroid of the
/// particles with the largest rest x (both within 1e-9 of the rest extent along x); "down" is
/// gravity's direction.
/// @param x0  3 by #P rest positions (m), the strip along +x
/// @param held  #P held-axis masks
/// @param x  3 by #P settled positions (m)
/// @param gravity  gravitational acceleration (m/s^2), non-zero
/// @param areal_density  the cloth's mass per area (kg/m^2)
/// @param edge  the platform's edge (m) along x
/// Throws std::invalid_argument when no held particle lies at or below edge or no particle
/// beyond it.
CantileverMetrics cantilever_metrics(const cloth::Matrix3X& x0,
                                     const std::vector<std::uint8_t>& held,
                                     const cloth::Matrix3X& x, const cloth::Vector3& gravity,
                                     double areal_density, double edge);

/// The rows of tests.csv for m, in the order written: chord_angle (deg), tip_deflection,
/// overhang, bending_length, bending_length_peirce (m), flexural_rigidity (N m).
std::vector<TestMetric> cantilever_rows(const CantileverMetrics& m);

}  // namespace clothbench
