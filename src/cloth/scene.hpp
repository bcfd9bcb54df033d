#pragma once
/// @file scene.hpp
/// The physical scene every engine builds: one cloth grid, gravity, spheres and held axes.
/// Plain aggregates with defaults (the course report's default scene); the harness fills them
/// from scenario files, the engines read them.

#include <vector>

#include "cloth/types.hpp"

namespace cloth {

/// Orientation of the flat initial cloth.
enum class Plane {
  xz,  ///< horizontal: i along +x, j along +z
  xy   ///< vertical: i along +x, j along +y
};

/// The cloth grid and its material.
struct ClothParams {
  int nu = 25;                       // particles along u (i)
  int nv = 25;                       // particles along v (j)
  double size_u = 4.0;               // m, extent along u
  double size_v = 4.0;               // m, extent along v
  Vector3 center = {0.0, 1.0, 0.0};  // m
  Plane plane = Plane::xz;
  double particle_mass = 1.0;   // kg, used when total_mass is 0
  double total_mass = 0.0;      // kg, spread evenly; 0: use particle_mass
  double k_structural = 2.0e4;  // N/m, 0: no structural springs
  double k_shear = 2.0e4;       // N/m, 0: no shear springs
  double k_bend = 2.0e4;        // N/m, 0: no bend springs
  double damping = 750.0;       // N s/m, along every spring
  double air_drag = 0.0;        // N s/m, viscous drag on every particle
};

/// A sphere obstacle; kinematic when its velocity is not zero.
struct Sphere {
  Vector3 center = {0.0, 0.0, 0.0};    // m, at t = 0
  double radius = 1.0;                 // m
  double restitution = 0.0;            // C_R, 0 (no bounce) to 1 (elastic)
  double friction = 0.0;               // Coulomb coefficient, 0: frictionless
  Vector3 velocity = {0.0, 0.0, 0.0};  // m/s, prescribed
  double margin = 0.01;                // m, contact shell thickness

  /// Centre at time t (s).
  Vector3 center_at(double t) const { return center + t * velocity; }
};

/// Everything an engine needs to build the same physical scene.
struct Scene {
  ClothParams cloth;
  Vector3 gravity = {0.0, -9.8, 0.0};  // m/s^2
  std::vector<Sphere> spheres;
  /// #P held-axis masks (AxisBits); empty means nothing is held.
  std::vector<std::uint8_t> held;

  int particle_count() const { return cloth.nu * cloth.nv; }
};

/// Column index of grid particle (i, j).
inline int particle_index(const ClothParams& c, int i, int j) {
  return j * c.nu + i;
}

/// The report's default scene: 25 x 25, 4 m x 4 m at y = 1 over a unit sphere, corners pinned;
/// per_edge other than 25 keeps the size and the total mass (625 kg).
Scene seed_scene(int per_edge = 25);

}  // namespace cloth
