#pragma once
/// @file hinge_bending.hpp
/// Force, energy and stiffness of the hinge model's bending (bending_form.hpp): with Q constant,
/// E = 1/2 sum_r x_r^T Q x_r, f_r = -Q x_r and df/dx = -Q on every axis (x_r, f_r rows r of
/// the 3 by #P positions and forces). No damping: the bend has no dashpot of its own. Each
/// kernel walks Q's nonzeros once with the three rows together and allocates nothing.

#include "cloth/model/bending_form.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// Adds the bending force -Q x_r to each row r of f; nothing for an empty form.
/// @param x  3 by #P positions (m)
/// @param f  3 by #P forces (N), accumulated into
void add_bending_forces(const BendingForm& form, const Matrix3X& x, Matrix3X& f);

/// Bending energy 1/2 sum_r x_r^T Q x_r (J); 0 for an empty form.
/// @param x  3 by #P positions (m)
double bending_energy(const BendingForm& form, const Matrix3X& x);

/// y += alpha K u with K = df/dx = -Q on every axis.
/// @param u  3 by #P
/// @param y  3 by #P, accumulated into
void add_bending_product(const BendingForm& form, const Matrix3X& u, double alpha, Matrix3X& y);

/// diag += alpha diag(K) = -alpha Q(p, p) on every axis of particle p.
/// @param diag  3 by #P, accumulated into
void add_bending_diagonal(const BendingForm& form, double alpha, Matrix3X& diag);

}  // namespace cloth
