#pragma once
/// @file energies.hpp
/// Mechanical energies of a cloth state, computed the same way for every engine.

#include "cloth/model/model.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// Energies of one state (J).
struct Energies {
  double kinetic = 0;            // J, sum 1/2 m |v|^2
  double gravity_potential = 0;  // J, -sum m g . x (zero at the origin)
  double elastic_potential = 0;  // J, sum 1/2 k (|d| - l0)^2, plus the hinge bending's

  double total() const { return kinetic + gravity_potential + elastic_potential; }
};

/// Energies of positions x and velocities v (each 3 by #P) in model m.
Energies compute_energies(const Model& m, const Matrix3X& x, const Matrix3X& v);

}  // namespace cloth
