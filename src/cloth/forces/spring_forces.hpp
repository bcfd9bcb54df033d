#pragma once
/// @file spring_forces.hpp
/// Spring and damping forces of the report, energies and strain, family by family and then
/// over the general list (spring_set.hpp):
///   f_a = -k (|x_a - x_b| - l0) d^ - c ((v_a - v_b) . d^) d^,   d^ = (x_a - x_b) / |x_a - x_b|

#include "cloth/model/spring_set.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// Adds every spring's elastic and damping force to f.
/// @param x    3 by #P positions (m)
/// @param v    3 by #P velocities (m/s)
/// @param f    3 by #P forces (N), accumulated into
/// @param buf  3 by #P scratch, overwritten
/// @return the power the spring dampers dissipate (W, >= 0)
double add_spring_forces(const SpringSet& springs, const Matrix3X& x, const Matrix3X& v,
                         Matrix3X& f, Matrix3X& buf);

/// Power dissipated by the spring dampers (W) without computing forces.
/// @param x  3 by #P positions (m)
/// @param v  3 by #P velocities (m/s)
double damping_power(const SpringSet& springs, const Matrix3X& x, const Matrix3X& v);

/// Elastic potential energy sum 1/2 k (|d| - l0)^2 (J).
/// @param x  3 by #P positions (m)
double elastic_energy(const SpringSet& springs, const Matrix3X& x);

/// Strain |d| / l0 - 1 over all springs; stretch and compression over the springs that hold
/// the cloth's surface (structural and shear), not the bend springs, which close up across a
/// fold without any overstretch.
struct StrainStats {
  double max_abs = 0;          // largest |strain|, every spring
  double mean_abs = 0;         // mean |strain|, every spring
  double max_stretch = 0;      // largest positive part of strain, non-bend springs
  double max_compression = 0;  // largest positive part of -strain, non-bend springs
};

/// Strain statistics of positions x (3 by #P); NaN positions make every statistic NaN.
StrainStats strain_stats(const SpringSet& springs, const Matrix3X& x);

}  // namespace cloth

namespace cloth {

/// True when every coordinate is finite and every spring's |strain| is at most limit.
/// Cheap enough to run every step: squared lengths only, no square root or division.
/// @param x  3 by #P positions (m)
bool within_strain(const SpringSet& springs, const Matrix3X& x, double limit);

/// True when every coordinate is finite and no structural or shear spring (no edge spring of a
/// mesh) is stretched past limit: l / l0 - 1 <= limit. Bend springs and compression are left
/// out: a fold closes the bend springs across it to nearly zero length, which is no blow-up.
/// Squared lengths only, like within_strain.
/// @param x  3 by #P positions (m)
bool within_stretch(const SpringSet& springs, const Matrix3X& x, double limit);

}  // namespace cloth
