#pragma once
/// @file bending_form.hpp
/// The hinge model's bending energy as a constant quadratic form (bend_model = "hinge").
///
/// For a cloth whose rest shape is flat, bending a region into a surface of principal
/// curvatures k1, k2 stores B/2 (k1^2 + k2^2) per unit area: the energy of an elastic plate
/// of Poisson ratio 0, B/2 ((k1 + k2)^2 - 2 (1 - nu) k1 k2), which is what a cloth needs (its
/// yarns bend independently: bending along the warp does not curl the weft, and a strip of any
/// width bends as the one-dimensional elastica of rigidity B says). In rest coordinates (s, t)
/// an isometric deformation has d^2 x / ds_i ds_j = II_ij n, so the energy is the squared
/// Hessian of the positions, B/2 sum_r int |Hess x_r|^2 dA: quadratic in the positions, as in
/// Bergou, Wardetzky, Harmon, Zorin and Grinspun 2006 ("A quadratic bending model for
/// inextensible surfaces"), who square the Laplacian instead (equal on an isometric bend, but
/// a plate of Poisson ratio 1 at a free edge: a strip then curls across as it bends along and
/// is softer than B says; build_laplacian_bending_form below, docs/methods.md).
///
/// Discretely x is linear on each rest triangle; its Hessian lives on the interior edges, the
/// jump of its derivative across each. Edge e's share at each end is
/// (K_e . x_r) / 2 n_e n_e^T, with n_e the edge's unit normal in the rest plane and
/// K_e . x_r = -|e| [d x_r / d n_e] the per-edge stencil (build_edge_bending_form), and their
/// sum at vertex v is M_v, the Hessian integrated over v's barycentric area A_v (its trace is
/// the cotangent Laplacian). With |M|^2 = M_uu^2 + M_vv^2 + 2 M_uv^2 in any orthonormal frame
/// of the plane:
///   E = 1/2 sum_r x_r^T Q x_r = B/2 sum_r [ sum_v |M_v(x_r)|^2 / A_v
///                                          - sum_(v on the boundary) M_v,nn(x_r)^2 / A_v
///                                          + sum_(b, u) a_bu M_u,nb(x_r)^2 / A_u^2 ].
/// At a boundary vertex v (outward normal n, the mean of its two boundary edges') the edges
/// along the boundary have one side, so M_v's nn part is not measured and is left out; that
/// part of v's area goes to its interior neighbours u (shares a_bu in proportion to the
/// cotangent weights joining them, equally when those are all zero), each adding its own
/// M_u's part along v's normal. On a grid (two triangles per cell, one diagonal) M_v is exact
/// for every quadratic at interior vertices and its tt and tn parts at boundary vertices, so
/// a uniformly bent sheet stores B/2 k^2 per area in every direction.
///
/// Q is constant, symmetric and positive semi-definite (a sum of squares), so the force is
/// -Q x_r row by row and the stiffness is -Q on every axis. It is zero for any rigid motion
/// and any affine in-plane map of the flat rest shape (x linear: no jump across any edge).

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

/// Builds Q (the squared Hessian above) for rigidity B from a flat rest shape. Particles held
/// on every axis are a rigid clamp: a triangle of three of them cannot bend and its area is
/// no vertex's, so A_v (and a_bu) count only the triangles with a free particle. At a clamp's
/// edge the kink between the held and the free triangles is then spread over the free side
/// alone, as it is in a clamped plate; counting the held side too would move the clamp half a
/// spacing back and lengthen a cantilever by h / 2 (its tip falls 2 h / L further at small
/// deflection, docs/methods.md).
/// @param x0         3 by #P rest positions (m), all in one plane
/// @param triangles  the surface (a particle in no triangle takes no part)
/// @param rigidity   B (N m), > 0
/// @param rigid      #P, 1 for a particle held on every axis; empty: none
/// @throws std::invalid_argument when the rest shape is not flat or B is not positive
BendingForm build_bending_form(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                               double rigidity, const std::vector<char>& rigid = {});

/// The form above with the Laplacian in place of the Hessian (Bergou et al. 2006's isometric
/// bending, E = B/2 sum_v (A~_v / A_v^2) (c_v . x_r)^2 over the interior vertices, c_v the
/// cotangent Laplacian's row, A~_v with the boundary vertices' areas), kept to measure against
/// (hinge_bending tests): on an isometric bend it stores the same, but its free edges act as
/// those of a plate of Poisson ratio 1 (docs/methods.md, "The hinge model").
/// @param x0  3 by #P flat rest positions (m)
BendingForm build_laplacian_bending_form(const Matrix3X& x0, const std::vector<Triangle>& triangles,
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
