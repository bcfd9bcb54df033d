#pragma once
/// @file bias_metrics.hpp
/// The bias-extension test (a strip of yarns at +-45 degrees to its length, length H at least
/// twice its width W, clamped at both short ends, one end pulled quasi-statically): the
/// central zone's shear angle, from the pin-jointed-net relation and measured from its
/// particles, the shear force per unit length from the clamp force by the energy balance of
/// the net's zones, and the shear stiffness, the initial slope of one against the other.
///
/// The pin-jointed net (inextensible yarns free to rotate at the crossings; Cao et al. 2008,
/// Composites Part A 39:1037-1053): the zones at the clamps stay undeformed, the central zone
/// (yarns touching neither clamp, area W (H - 3W/2)) shears by gamma, the four zones between
/// (area W^2 in all) by gamma / 2. Along the centre line the central zone spans H - W, so
/// H - W + d = sqrt(2) (H - W) cos(pi/4 - gamma/2), d the clamp's displacement.

#include <cstdint>
#include <vector>

#include "cloth/model/scene.hpp"
#include "cloth/model/spring_set.hpp"
#include "cloth/model/types.hpp"
#include "harness/fabric/test_metric.hpp"

namespace clothbench {

/// Where a bias-extension scene measures.
struct BiasSetup {
  cloth::Vector3 axis = cloth::Vector3::UnitX();    // unit, the extension direction (length)
  cloth::Vector3 across = cloth::Vector3::UnitZ();  // unit, in the sheet, across the strip
  double length = 0;   // m, H: rest distance from the clamp's last particle to the handle's first
  double width = 0;    // m, W: the strip's rest extent across
  double section = 0;  // m, rest coordinate along axis of the central section (between particles)
  std::vector<int> central;  // the central zone's particles: rest within W/4 of the centre
                             // along and across (inside the pure-shear zone for H >= 2 W)
};

/// The setup of a strip whose fixed clamp is every particle held on all axes
/// (held[p] == kHoldAll) and whose moving clamp is handle_particles.
/// @param x0  3 by #P rest positions (m)
/// @param held  #P held-axis masks
/// @param handle_particles  the handle's particle indices
/// @param axis  unit extension direction; across: unit, in the sheet, normal to it
/// Throws std::invalid_argument when there is no clamp, no handle, a clamped particle lies at
/// or beyond the handle's nearest one along axis, or the central zone has fewer than 3
/// particles.
BiasSetup bias_setup(const cloth::Matrix3X& x0, const std::vector<std::uint8_t>& held,
                     const std::vector<int>& handle_particles, const cloth::Vector3& axis,
                     const cloth::Vector3& across);

/// The central zone's shear angle (rad) of the pin-jointed net at the clamp's displacement d
/// (m): pi/2 - 2 acos[(H - W + d) / (sqrt(2) (H - W))]; NaN where the argument leaves [-1, 1]
/// or H <= W.
double pin_jointed_angle(double length, double width, double d);

/// The central zone's shear angle (rad) measured at positions x: pi/2 less the angle between
/// the deformed yarn directions F (axis + across) / sqrt(2) and F (axis - across) / sqrt(2),
/// F the least-squares affine map (3 by 2) from the zone's rest coordinates (along, across)
/// to its positions. NaN when the zone's rest coordinates do not span the plane.
/// @param x0  3 by #P rest positions (m); x: 3 by #P positions (m)
double central_shear_angle(const cloth::Matrix3X& x0, const cloth::Matrix3X& x,
                           const BiasSetup& setup);

/// The axial force (N) across setup's section at positions x: the sum over the springs whose
/// ends lie on both sides of it (at rest) of their elastic force's component along the axis,
/// positive when stretched (the clamp force in quasi-static equilibrium). Dampers left out.
double bias_section_force(const cloth::SpringSet& springs, const cloth::Matrix3X& x0,
                          const cloth::Matrix3X& x, const BiasSetup& setup);

/// One frame of the bias-extension curve.
struct BiasPoint {
  double t = 0;                // s
  double displacement = 0;     // m, d: the handle's prescribed displacement along the axis
  double force = 0;            // N, F: bias_section_force
  double angle_pin = 0;        // rad, pin_jointed_angle at d
  double angle = 0;            // rad, central_shear_angle (measured)
  double shear_force = 0;      // N/m, F_s at the measured angle (normalise_shear_force)
  double shear_force_pin = 0;  // N/m, F_s at the pin-jointed angle (normalise_shear_force)
};

/// The shear force per unit length F_s (N/m) at each angle (rad) with each clamp force (N),
/// in order (angle and force #K each), from the energy balance
/// of the net's zones, F d' = W (H - 3W/2) T(gamma) gamma' + W^2 T(gamma/2) gamma'/2 with the
/// torque per unit area T = F_s cos(gamma) and d' = (H - W) (cos(gamma/2) - sin(gamma/2))
/// gamma' / 2 (the derivative of the relation above):
/// F_s(gamma) = [(H/W - 1) F (cos(gamma/2) - sin(gamma/2)) - W F_s(gamma/2) cos(gamma/2)]
///              / ((2H - 3W) cos(gamma)),
/// the normalisation of Harrison et al. 2004 and Cao et al. 2008; F_s(gamma/2) interpolated
/// linearly between the earlier points (and 0 at gamma = 0), or, before any earlier point
/// reaches gamma/2, taken as F_s(gamma) / 2 (a linear net). Returns #K values.
std::vector<double> normalise_shear_force(const std::vector<double>& angle,
                                          const std::vector<double>& force, double length,
                                          double width);

/// The curve of one run: a point per frame at times t with positions x[k] (3 by #P each), the
/// displacement from the handle's prescribed motion, shear forces normalised at the measured
/// angles and at the pin-jointed ones.
std::vector<BiasPoint> bias_curve(const cloth::SpringSet& springs, const cloth::Matrix3X& x0,
                                  const BiasSetup& setup, const cloth::Motion& handle,
                                  const std::vector<double>& t,
                                  const std::vector<cloth::Matrix3X>& x);

/// The shear stiffness (N/m per rad): the least-squares slope (with intercept) of the shear
/// force per unit length against the angle over the points with 0 < angle <= fit_angle
/// (degrees): the measured angle and shear_force, or with pin_jointed the pin-jointed angle
/// and shear_force_pin; NaN with fewer than 3.
double shear_slope(const std::vector<BiasPoint>& curve, double fit_angle, bool pin_jointed = false);

/// The rows of tests.csv for a curve, in the order written: shear_stiffness (N/m/rad, the
/// measured angle's), shear_stiffness_pin_jointed (N/m/rad, the relation's angle's),
/// fit_angle (deg, the range of their fits, as given), final_shear_angle (deg, measured) and
/// final_shear_angle_pin_jointed (deg) at the last point, max_force (N) (NaN for an empty
/// curve).
std::vector<TestMetric> bias_rows(const std::vector<BiasPoint>& curve, double fit_angle);

}  // namespace clothbench
