#pragma once
/// @file model.hpp
/// A scene turned into arrays: rest positions, masses, held axes, springs and obstacles.

#include <vector>

#include "cloth/model/scene.hpp"
#include "cloth/model/spring_set.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// The discrete cloth every engine and every metric works from.
struct Model {
  int nu = 0;            // a grid's particles along u; a mesh's vertices
  int nv = 0;            // a grid's particles along v; 1 for a mesh
  bool is_mesh = false;  // a triangle mesh: its springs are a general list, not grid families
  Matrix3X x0;           // 3 by #P initial (rest) positions (m)
  VectorX mass;          // #P particle masses (kg)
  VectorX inv_mass;      // #P inverse masses (1/kg)
  Matrix3X free;         // 3 by #P: 1 where the axis moves, 0 where it is held
  bool any_held = false;
  SpringSet springs;
  std::vector<Triangle>
      triangles;  // the surface: grid cells split along a diagonal, or a mesh's faces
  Vector3 gravity = Vector3::Zero();  // m/s^2
  double air_drag = 0;                // N s/m
  Vector3 wind = Vector3::Zero();     // m/s
  std::vector<Sphere> spheres;
  Shapes shapes;
  std::vector<Handle> handles;  // their particles are held on every axis in free
  bool self_collision = false;  // keep the layers at least thickness apart
  double thickness = 0;         // m
  double self_friction = 0;     // Coulomb coefficient, cloth on cloth

  int particle_count() const { return static_cast<int>(mass.size()); }
  /// Adds the air drag -air_drag (v - wind) at velocities v (3 by #P, m/s) to f (N).
  void add_drag(const Matrix3X& v, Matrix3X& f) const {
    if (air_drag == 0.0) return;
    f -= air_drag * v;
    if (!wind.isZero())
      for (int r = 0; r < 3; ++r) f.row(r).array() += air_drag * wind[r];
  }
  /// Power the air takes out of the cloth at velocities v (W): air_drag (v - wind) . v.
  double drag_power(const Matrix3X& v) const {
    if (air_drag == 0.0) return 0.0;
    return air_drag * (v.squaredNorm() - (wind.isZero() ? 0.0 : wind.dot(v.rowwise().sum())));
  }
};

/// Rest positions of the scene's cloth: its mesh's vertices or its grid's particles.
/// @return 3 by #P positions (m)
Matrix3X rest_positions(const Scene& scene);

/// Grid positions of the flat cloth described by c.
/// @return 3 by #P positions (m)
Matrix3X grid_positions(const ClothParams& c);

/// Triangles of an nu by nv grid (particle p = j nu + i): two per cell, split along the
/// diagonal from (i, j) to (i + 1, j + 1), as (p00, p10, p11) and (p00, p11, p01), cells in
/// order j then i. None when nu or nv is below 2.
std::vector<Triangle> grid_triangles(int nu, int nv);

/// Builds the model of a scene; throws std::invalid_argument for an impossible scene.
Model build_model(const Scene& scene);

}  // namespace cloth
