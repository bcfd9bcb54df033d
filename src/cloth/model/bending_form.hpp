#pragma once
/// @file bending_form.hpp
/// The hinge model's bending energy as a constant quadratic form (bend_model = "hinge").
///
/// For a cloth whose rest shape is flat, bending a region into a surface of principal
/// curvatures k1, k2 stores B/2 (k1 + k2)^2 per unit area; for the isometric bending cloth
/// does (k1 k2 = 0) this is the plate energy B/2 k^2 of any elastic plate, whatever its
/// Poisson ratio. Since the mean-curvature normal of an isometric deformation is the Laplacian
/// of the positions, Delta x = (k1 + k2) n, the energy is quadratic in the positions (Bergou,
/// Wardetzky, Harmon, Zorin and Grinspun 2006, "A quadratic bending model for inextensible
/// surfaces"), with the Laplacian taken at the rest shape:
///   E = 1/2 sum_r x_r^T Q x_r,   Q = B sum_v (A~_v / A_v^2) c_v c_v^T,
/// x_r row r of the 3 by #P positions, c_v the cotangent Laplacian's row at interior vertex v
/// (c_v[u] = (cot a + cot b) / 2 for each edge vu with opposite rest angles a and b,
/// c_v[v] = -sum_u c_v[u]), so c_v . x_r = (Delta x)_r integrated over v's area; A_v is v's
/// barycentric area (a third of its triangles') and A~_v the area its density stands for:
/// A_v plus the shares of the boundary vertices next to it. A boundary vertex's cotangent
/// Laplacian is not zero on a flat sheet, so it has no term of its own; its area goes to its
/// interior neighbours in proportion to the cotangent weights joining them (equally when
/// those are all zero), so that sum_v A~_v is the cloth's area and a uniformly bent sheet
/// stores exactly B/2 k^2 times its area on a grid. On a grid (two triangles per cell, one
/// diagonal, model.hpp) the diagonal's weight is zero and c_v is the five-point Laplacian:
/// the energy does not depend on the direction of the bend.
///
/// Q is constant, symmetric and positive semi-definite, so the force is -Q x_r row by row and
/// the stiffness is -Q on every axis. It is zero for any rigid motion and any affine in-plane
/// map of the flat rest shape (the cotangent Laplacian is exact for linear functions).

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <vector>

#include "cloth/model/types.hpp"

namespace cloth {

/// The constant form Q of the hinge model; empty for a cloth with bend springs.
struct BendingForm {
  Eigen::SparseMatrix<double> q;  // #P by #P, symmetric, N/m: E = 1/2 sum_r x_r^T Q x_r

  /// True when there is no hinge bending.
  bool empty() const { return q.nonZeros() == 0; }
};

/// Builds Q for rigidity B from a flat rest shape.
/// @param x0         3 by #P rest positions (m), all in one plane
/// @param triangles  the surface (a particle in no triangle takes no part)
/// @param rigidity   B (N m), > 0
/// @throws std::invalid_argument when the rest shape is not flat or B is not positive
BendingForm build_bending_form(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                               double rigidity);

/// The per-edge form of Bergou et al. 2006 for comparison (hinge_bending tests): per interior
/// edge ab with opposite vertices c, d, E_e = B/2 |K x|^2 / (A0 + A1) with K = (cot b0 + cot b1,
/// cot a0 + cot a1, -(cot a0 + cot b0), -(cot a1 + cot b1)) from the rest angles at a and b
/// in each triangle: their 3 / (A0 + A1) times 1/3, the constant a cylinder along a grid axis
/// or on an equilateral mesh needs.
/// @param x0  3 by #P flat rest positions (m)
BendingForm build_edge_bending_form(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                                    double rigidity);

/// The same form between renumbered particles: Q'(new_of_old[p], new_of_old[q]) = Q(p, q).
/// @param new_of_old  #P, a permutation
BendingForm renumbered(const BendingForm& form, const std::vector<int>& new_of_old);

}  // namespace cloth
