#pragma once
/// @file metrics.hpp
/// Per-frame metrics of one engine's state, and the divergence of two engines' states.
/// Computed from positions and velocities alone, so every engine is measured the same way.

#include <cmath>
#include <vector>

#include "cloth/analysis/self_intersection.hpp"
#include "cloth/model/model.hpp"
#include "cloth/model/types.hpp"

namespace clothbench {

/// What an engine has booked of its energy since the start (J): the terms of the balance
///   energy_error = total + dissipated - contact_work - collider_work - handle_work - unbooked
///                  - initial total.
struct EnergyBooks {
  double dissipated = 0;     // J, taken out by the spring dampers and air drag
  double contact_work = 0;   // J, net work of the contact response relative to the colliders
                             // (custom engine)
  double unbooked = 0;       // J, balance of a Bullet engine's steps with a contact, and of
                             // an engine's steps whose handles moved by projection
  double handle_work = 0;    // J, the handles' holders' work, booked by the harness
  double collider_work = 0;  // J, the moving colliders' work (custom engine)
};

/// The energy error (J) of a state whose total energy is total, with books kept since a start
/// whose total energy was e0: what the engine's scheme created (> 0) or lost (< 0).
inline double energy_error(double total, const EnergyBooks& books, double e0) {
  return total + books.dissipated - books.contact_work - books.collider_work - books.handle_work -
         books.unbooked - e0;
}

/// One row of frames.csv (without the engine name).
struct FrameMetrics {
  double t = 0;                    // s
  double kinetic = 0;              // J
  double gravity_potential = 0;    // J
  double elastic_potential = 0;    // J
  double dissipated = 0;           // J, taken out by dampers and drag so far
  double contact_work = 0;         // J, net work of the contact response so far, relative to
                                   // the colliders
  double collider_work = 0;        // J, work of the moving colliders' motion so far
  double unbooked = 0;             // J, balance no book explains (Bullet contact steps)
  double handle_work = 0;          // J, work of the handles' holders so far
  double total_energy = 0;         // J, kinetic + both potentials
  double energy_error = 0;         // J, total + dissipated - contact_work - collider_work
                                   // - handle_work - unbooked - initial
  double max_strain = 0;           // largest |l / l0 - 1|
  double mean_strain = 0;          // mean |l / l0 - 1|
  double max_stretch = 0;          // largest l / l0 - 1 > 0 of a structural, shear or edge spring
  double max_compression = 0;      // largest 1 - l / l0 > 0 of the same springs
  int self_intersections = -1;     // edge-triangle crossings of the cloth with itself; -1: unknown
  double min_self_distance = NAN;  // m, smallest gap between parts more than two rings apart,
                                   // capped at half the mean rest edge length; NaN: unknown
  Eigen::Vector3d com = Eigen::Vector3d::Zero();  // m, mass-weighted centre
  double min_y = 0;                               // m, lowest particle height
  double max_penetration = 0;                     // m, deepest particle below a collider's surface
  double shadow_area = 0;  // m^2, cloth shadow on the plane normal to gravity
  bool stable = true;
  int contacts = -1;  // particles in contact at the frame's last step; -1: the engine cannot say
  Eigen::Vector3d contact_force = Eigen::Vector3d::Constant(NAN);  // N, the colliders' push
                                                                   // averaged over the frame
};

/// One row of divergence.csv (without the engine names).
struct Divergence {
  double t = 0;                       // s
  double rms_distance = 0;            // m, RMS over particles of |x - x_ref|
  double max_distance = 0;            // m
  double com_distance = 0;            // m
  double energy_difference = 0;       // J, total energy minus the reference's
  double shadow_area_difference = 0;  // m^2
};

/// Cells along the longer side of the shadow raster (area error about perimeter / 2 cells).
constexpr int kShadowResolution = 512;

/// Area (m^2) of the union of the model's triangles projected along gravity.
/// @param x  3 by #P positions (m)
double shadow_area(const cloth::Model& model, const Eigen::Vector3d& gravity,
                   const cloth::Matrix3X& x);

/// Metrics of state (x, v) at time t; e0 is the initial total energy. With a meter (see
/// cloth::rest_shape_meter) the self-intersection columns are measured, else left unknown.
/// @param x  3 by #P positions (m)
/// @param v  3 by #P velocities (m/s)
FrameMetrics frame_metrics(const cloth::Model& model, double t, const cloth::Matrix3X& x,
                           const cloth::Matrix3X& v, const EnergyBooks& books, double e0,
                           const cloth::SelfIntersectionMeter* meter = nullptr);

/// The energy scale of the blow-up test (J): the cloth's weight times its largest rest extent
/// (the work of lifting the cloth by its own size, which bounds the potential energy a drape
/// exchanges) plus the largest kinetic and the largest elastic energy seen so far. Every term
/// is unchanged by moving the origin, so the test does not depend on where y = 0 is.
class EnergyScale {
 public:
  /// @param model  the scene: masses, gravity and rest positions x0 (3 by #P)
  explicit EnergyScale(const cloth::Model& model);
  /// Takes the kinetic and elastic energy (J) of a state into the running maxima.
  void observe(double kinetic, double elastic);
  /// The scale (J).
  double value() const { return m_weight_extent + m_kinetic + m_elastic; }
  /// Whether an energy error (J) fails the blow-up test at limit times the scale. One-sided
  /// (a scheme that loses energy is dissipative, not unstable); a NaN error fails.
  bool exceeded_by(double error, double limit) const { return !(error <= limit * value()); }

 private:
  double m_weight_extent = 0;  // J
  double m_kinetic = 0;        // J, largest so far
  double m_elastic = 0;        // J, largest so far
};

/// Static residual of state (x, v): the largest net force (springs, dampers, drag and
/// gravity) on a particle with a free axis, over the free axes, divided by that particle's
/// weight; 0 at an exact equilibrium. A particle within a margin of a sphere's contact shell
/// (radius + 2 margin) gets the force the sphere can give: a push along the outward normal
/// that cancels the net force into the sphere, and Coulomb friction up to mu times that push
/// against the tangential rest. NaN for a scene without gravity.
/// @param x  3 by #P positions (m)
/// @param v  3 by #P velocities (m/s)
double static_residual(const cloth::Model& model, double t, const cloth::Matrix3X& x,
                       const cloth::Matrix3X& v);

/// Divergence of state x (3 by #P) from the reference state x_ref, with their metrics.
Divergence divergence(const cloth::Matrix3X& x, const FrameMetrics& m, const cloth::Matrix3X& x_ref,
                      const FrameMetrics& m_ref);

/// Support area (m^2) under the cloth for the drape coefficient: held disks, else the tops of
/// the fixed cylinders (the Cusick disk) under a horizontal cloth, else the cross-sections of
/// the fixed spheres it drapes over; 0 when the scene has no support (a vertical cloth, a
/// collider that moves), so no coefficient is given.
/// @param horizontal  the cloth starts flat in the x-z plane
double support_area(const std::vector<double>& disk_radii,
                    const std::vector<cloth::Sphere>& spheres, bool horizontal,
                    const std::vector<cloth::Cylinder>& cylinders = {});

/// Cusick drape coefficient (shadow - support) / (cloth - support).
double drape_coefficient(double shadow, double support, double cloth_area);

}  // namespace clothbench
