#pragma once
/// @file scene.hpp
/// The physical scene every engine builds: one cloth grid, gravity, wind, rigid colliders
/// (spheres, planes, boxes, capsules, cylinders), held axes and handles.
/// Plain aggregates with defaults (the course report's default scene); the harness fills them
/// from scenario files, the engines read them.

#include <array>
#include <memory>
#include <vector>

#include "cloth/model/types.hpp"

namespace cloth {

/// Orientation of the flat initial cloth.
enum class Plane {
  xz,  ///< horizontal: i along +x, j along +z
  xy   ///< vertical: i along +x, j along +y
};

/// How a cloth resists bending.
enum class BendModel {
  springs,  ///< bend springs (k_bend) across every interior edge (a grid's: two steps apart)
  hinge     ///< a constant quadratic form with rigidity B (bending_form.hpp); no bend springs
};

/// "springs" or "hinge".
const char* bend_model_name(BendModel model);

/// The cloth grid and its material.
struct ClothParams {
  int nu = 25;                       // particles along u (i)
  int nv = 25;                       // particles along v (j)
  double size_u = 4.0;               // m, extent along u
  double size_v = 4.0;               // m, extent along v
  Vector3 center = {0.0, 1.0, 0.0};  // m
  Plane plane = Plane::xz;
  double particle_mass = 1.0;   // kg, used when total_mass and areal_density are 0
  double total_mass = 0.0;      // kg, spread evenly (a mesh: by area); 0: not given
  double areal_density = 0.0;   // kg/m^2, mass per area of cloth; 0: not given
  double k_structural = 2.0e4;  // N/m, 0: no structural springs
  double k_shear = 2.0e4;       // N/m, 0: no shear springs
  double k_bend = 2.0e4;        // N/m, 0: no bend springs; not used by the hinge model
  BendModel bend_model = BendModel::springs;
  double bending_rigidity = 0.0;  // N m, B of the hinge model (> 0 there), per unit width
  double damping = 750.0;         // N s/m, along every spring
  double air_drag = 0.0;          // N s/m, viscous drag on every particle
  bool self_collision = false;    // keep layers of the cloth apart (engines that can)
  double thickness = 0.004;       // m, the distance self-contact keeps layers apart
  double self_friction = 0.0;     // Coulomb coefficient of cloth on cloth
  // a grid's structural springs along v (k_structural is then those along u); < 0: the same
  double k_structural_v = -1.0;  // N/m

  /// The stiffness of a grid's structural springs along v (N/m): k_structural_v, or
  /// k_structural when it is < 0 (the same along u and v).
  double structural_v() const { return k_structural_v < 0.0 ? k_structural : k_structural_v; }
  /// True when a grid's structural springs differ along u and v.
  bool anisotropic() const { return structural_v() != k_structural; }
};

/// Prescribed rigid translation, the one mechanism of moving colliders and handles: a constant
/// velocity, or a piecewise-linear path of displacements [t, dx, dy, dz] (times strictly
/// increasing from 0, zero displacement at t = 0, held at the last displacement after it).
struct Motion {
  Vector3 velocity = {0.0, 0.0, 0.0};       // m/s, used when path is empty
  std::vector<std::array<double, 4>> path;  // [s, m, m, m]

  /// Displacement from the start at time t (s).
  Vector3 displacement(double t) const;
  /// Velocity at time t (s): the velocity of the path segment that starts at or before t.
  Vector3 velocity_at(double t) const;
  /// True when the motion ever moves.
  bool moves() const { return !path.empty() || !velocity.isZero(); }
};

/// What every rigid collider has: its contact response and its motion. Infinitely heavy,
/// never rotating.
struct Collider : Motion {
  double restitution = 0.0;  // C_R, 0 (no bounce) to 1 (elastic)
  double friction = 0.0;     // Coulomb coefficient, 0: frictionless
  double margin = 0.01;      // m, contact shell thickness
};

/// A sphere obstacle.
struct Sphere : Collider {
  Vector3 center = {0.0, 0.0, 0.0};  // m, at t = 0
  double radius = 1.0;               // m

  /// Centre at time t (s).
  Vector3 center_at(double t) const { return center + displacement(t); }
};

/// A half-space: solid behind the plane through point with outward normal.
struct HalfSpace : Collider {
  Vector3 point = {0.0, 0.0, 0.0};   // m, at t = 0
  Vector3 normal = {0.0, 1.0, 0.0};  // unit, out of the solid
};

/// An axis-aligned box.
struct Box : Collider {
  Vector3 center = {0.0, 0.0, 0.0};        // m, at t = 0
  Vector3 half_extents = {0.5, 0.5, 0.5};  // m, each > 0
};

/// The points within radius of segment a-b.
struct Capsule : Collider {
  Vector3 a = {-1.0, 0.0, 0.0};  // m, at t = 0
  Vector3 b = {1.0, 0.0, 0.0};   // m, at t = 0, not a
  double radius = 0.05;          // m
};

/// A solid cylinder with its axis along y.
struct Cylinder : Collider {
  Vector3 center = {0.0, 0.0, 0.0};  // m, at t = 0
  double radius = 0.1;               // m
  double height = 0.02;              // m
};

/// The colliders other than spheres.
struct Shapes {
  std::vector<HalfSpace> planes;
  std::vector<Box> boxes;
  std::vector<Capsule> capsules;
  std::vector<Cylinder> cylinders;

  bool empty() const {
    return planes.empty() && boxes.empty() && capsules.empty() && cylinders.empty();
  }
  /// Shapes in all.
  std::size_t count() const {
    return planes.size() + boxes.size() + capsules.size() + cylinders.size();
  }
};

/// Particles moved exactly along a motion (all three axes held).
struct Handle {
  std::vector<int> particles;  // particle indices
  Motion motion;
};

struct TriangleMesh;

/// Everything an engine needs to build the same physical scene.
struct Scene {
  ClothParams cloth;  // a mesh's cloth reads only the masses, stiffness (no shear) and damping
  /// The cloth as a triangle mesh (vertices, faces and named groups); null: the grid of cloth.
  std::shared_ptr<const TriangleMesh> mesh;
  Vector3 gravity = {0.0, -9.8, 0.0};  // m/s^2
  Vector3 wind = {0.0, 0.0, 0.0};      // m/s, air velocity for cloth.air_drag
  std::vector<Sphere> spheres;
  Shapes shapes;
  std::vector<Handle> handles;
  /// #P held-axis masks (AxisBits); empty means nothing is held.
  std::vector<std::uint8_t> held;

  /// The mesh's vertices, or the grid's nu nv particles.
  int particle_count() const;
};

/// Column index of grid particle (i, j).
inline int particle_index(const ClothParams& c, int i, int j) {
  return j * c.nu + i;
}

/// The report's default scene: 25 x 25, 4 m x 4 m at y = 1 over a unit sphere, corners pinned;
/// per_edge other than 25 keeps the size and the total mass (625 kg).
Scene seed_scene(int per_edge = 25);

}  // namespace cloth
