#pragma once
/// @file metrics.hpp
/// Per-frame metrics of one engine's state, and the divergence of two engines' states.
/// Computed from positions and velocities alone, so every engine is measured the same way.

#include <vector>

#include "cloth/model.hpp"
#include "cloth/types.hpp"

namespace clothbench {

/// One row of frames.csv (without the engine name).
struct FrameMetrics {
  double t = 0;                  // s
  double kinetic = 0;            // J
  double gravity_potential = 0;  // J
  double elastic_potential = 0;  // J
  double dissipated = 0;         // J, taken out by dampers, drag and contact so far
  double total_energy = 0;       // J, kinetic + both potentials
  double energy_error = 0;       // J, total + dissipated - initial total
  double max_strain = 0;         // largest |l / l0 - 1|
  double mean_strain = 0;        // mean |l / l0 - 1|
  Eigen::Vector3d com = Eigen::Vector3d::Zero();  // m, mass-weighted centre
  double min_y = 0;                               // m, lowest particle height
  double max_penetration = 0;                     // m, deepest particle below a sphere's surface
  double shadow_area = 0;  // m^2, cloth shadow on the plane normal to gravity
  bool stable = true;
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

/// Area (m^2) of the union of the grid's triangles projected along gravity.
/// @param x  3 by #P positions (m); triangles are the grid's cells split along a diagonal
double shadow_area(const cloth::Model& model, const Eigen::Vector3d& gravity,
                   const cloth::Matrix3X& x);

/// Metrics of state (x, v) at time t; e0 is the initial total energy.
/// @param x  3 by #P positions (m)
/// @param v  3 by #P velocities (m/s)
FrameMetrics frame_metrics(const cloth::Model& model, double t, const cloth::Matrix3X& x,
                           const cloth::Matrix3X& v, double dissipated, double e0);

/// Divergence of state x (3 by #P) from the reference state x_ref, with their metrics.
Divergence divergence(const cloth::Matrix3X& x, const FrameMetrics& m, const cloth::Matrix3X& x_ref,
                      const FrameMetrics& m_ref);

/// Support area (m^2) under the cloth for the drape coefficient: the held disks of the table
/// scene, else the cross-sections of the fixed spheres a horizontal cloth drapes over; 0 when
/// the scene has no support (a vertical cloth, a sphere that moves), so no coefficient is given.
/// @param horizontal  the cloth starts flat in the x-z plane
double support_area(const std::vector<double>& disk_radii,
                    const std::vector<cloth::Sphere>& spheres, bool horizontal);

/// Cusick drape coefficient (shadow - support) / (cloth - support).
double drape_coefficient(double shadow, double support, double cloth_area);

}  // namespace clothbench
