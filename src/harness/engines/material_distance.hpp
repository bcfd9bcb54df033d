#pragma once
/// @file material_distance.hpp
/// Distances between cloths on grids of different sizes, at common material points.

#include "cloth/model/types.hpp"

namespace clothbench {

/// Position at material coordinates (u, v) in [0, 1]^2 of a grid, by bilinear interpolation.
/// @param x   3 by #P positions of an nu by nv grid (p = j * nu + i, u = i / (nu - 1))
cloth::Vector3 bilinear_position(const cloth::Matrix3X& x, int nu, int nv, double u, double v);

/// RMS over the particles of grid a of the distance to grid b at the same material point.
/// @param a  3 by #P positions of an a_nu by a_nv grid
/// @param b  3 by #P positions of a b_nu by b_nv grid, interpolated bilinearly
double material_rms_distance(const cloth::Matrix3X& a, int a_nu, int a_nv, const cloth::Matrix3X& b,
                             int b_nu, int b_nv);

}  // namespace clothbench
