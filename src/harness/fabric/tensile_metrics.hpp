#pragma once
/// @file tensile_metrics.hpp
/// The strip-tensile test (ISO 13934-1 strip geometry, quasi-static extension by a handle):
/// the strain the handle imposes, the force per width across the strip's central section,
/// and the tensile stiffness, the initial slope of one against the other.

#include <cstdint>
#include <vector>

#include "cloth/model/scene.hpp"
#include "cloth/model/spring_set.hpp"
#include "cloth/model/types.hpp"
#include "harness/fabric/cantilever_metrics.hpp"

namespace clothbench {

/// Where a strip-tensile scene measures: the extension axis, the gauge between the clamp and
/// the handle, the strip's width and the central section.
struct TensileSetup {
  cloth::Vector3 axis = cloth::Vector3::UnitX();  // unit, the extension direction
  double gauge = 0;    // m, L0: rest distance from the clamp's last particle to the handle's first
  double width = 0;    // m, W: the strip's rest extent across the axis
  double section = 0;  // m, rest coordinate along axis of the central section (between particles)
  double clamp = 0;    // m, rest coordinate along axis of the clamp's last particle
};

/// The setup of a strip whose clamp is every particle held on all axes (held[p] == kHoldAll)
/// and whose handle is handle_particles. The section is the middle of the gap between
/// particles' rest coordinates nearest the middle of the gauge, so no particle lies on it.
/// @param x0  3 by #P rest positions (m)
/// @param held  #P held-axis masks
/// @param handle_particles  the handle's particle indices
/// @param axis  unit extension direction
/// @param width  the strip's rest width (m)
/// Throws std::invalid_argument when there is no clamp, no handle, or a clamped particle lies
/// at or beyond the handle's nearest particle along axis.
TensileSetup tensile_setup(const cloth::Matrix3X& x0, const std::vector<std::uint8_t>& held,
                           const std::vector<int>& handle_particles, const cloth::Vector3& axis,
                           double width);

/// The tension across setup's section at positions x, per unit width (N/m): the sum over the
/// springs whose ends lie on both sides of it (at rest) of their elastic force's component
/// along the axis, positive when stretched. Dampers are left out (quasi-static).
/// @param springs  the cloth's springs (rest lengths, stiffnesses)
/// @param x0  3 by #P rest positions (m)
/// @param x  3 by #P positions (m)
double section_force_per_width(const cloth::SpringSet& springs, const cloth::Matrix3X& x0,
                               const cloth::Matrix3X& x, const TensileSetup& setup);

/// One frame of the force-strain curve.
struct TensilePoint {
  double t = 0;                // s
  double strain = 0;           // 1, the handle's displacement along the axis over the gauge
  double force_per_width = 0;  // N/m, section_force_per_width
};

/// The curve of one run: a point per frame at times t with positions x[k] (3 by #P each), the
/// strain from the handle's prescribed motion.
std::vector<TensilePoint> tensile_curve(const cloth::SpringSet& springs, const cloth::Matrix3X& x0,
                                        const TensileSetup& setup, const cloth::Motion& handle,
                                        const std::vector<double>& t,
                                        const std::vector<cloth::Matrix3X>& x);

/// The tensile stiffness (N/m): the least-squares slope (with intercept) of force per width
/// against strain over the points with 0 < strain <= fit_strain; NaN with fewer than 3.
double tensile_slope(const std::vector<TensilePoint>& curve, double fit_strain);

/// The rows of tests.csv for a curve, in the order written: tensile_stiffness (N/m),
/// fit_strain (1, the range of its fit), max_strain (1) and max_force_per_width (N/m)
/// reached (NaN for an empty curve).
std::vector<TestMetric> tensile_rows(const std::vector<TensilePoint>& curve, double fit_strain);

}  // namespace clothbench
