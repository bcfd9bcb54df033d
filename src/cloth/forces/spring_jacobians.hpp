#pragma once
/// @file spring_jacobians.hpp
/// Analytic Jacobians of the spring forces, applied matrix-free.
///
/// For a spring from p to q (a family's anchor p and its partner, or a list's ends a and b)
/// with d = x_q - x_p, l = |d|, d^ = d / l and b = 1 - l0 / l:
///   df_p/dx_q = J = k ((1 - b) d^ d^T + b I),   df_p/dx_p = -J,
///   df_p/dv_q = c d^ d^T,                        df_p/dv_p = -c d^ d^T.
/// With clamping, b is replaced by max(b, 0): a compressed spring then contributes no
/// negative transverse stiffness and the implicit system stays positive definite. The damping
/// force's dependence on positions is left out, as in Baraff and Witkin's linearisation.

#include <vector>

#include "cloth/model/spring_set.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// Per spring direction d^ and transverse factor b, for each group of springs (spring_set.hpp).
struct SpringLinearization {
  /// one 4 by slots matrix per group (SpringSet::groups(): each family, then the general list
  /// with one slot per spring): rows d^x, d^y, d^z, b (0 where no spring)
  std::vector<Eigen::Matrix<double, 4, Eigen::Dynamic, Eigen::RowMajor>> dirs;
};

/// Linearises every spring at positions x (3 by #P).
/// @param clamp_compressed  replace b by max(b, 0)
/// @param unclamped         if given, also the linearisation with b as it is (written)
void linearize_springs(const SpringSet& springs, const Matrix3X& x, bool clamp_compressed,
                       SpringLinearization& lin, SpringLinearization* unclamped = nullptr);

/// y += alpha K u + beta D u, with K = df/dx and D = df/dv of the springs.
/// @param u    3 by #P
/// @param y    3 by #P, accumulated into
/// @param buf  3 by #P scratch
void add_jacobian_product(const SpringSet& springs, const SpringLinearization& lin,
                          const Matrix3X& u, double alpha, double beta, Matrix3X& y, Matrix3X& buf);

/// y += alpha K u + beta D0 u in one pass over the springs, with K from lin_k and D0's
/// directions from lin_d: the product implicit Euler's conjugate gradients need, equal to
/// add_jacobian_product(lin_k, alpha, 0) followed by add_jacobian_product(lin_d, 0, beta).
void add_newton_product(const SpringSet& springs, const SpringLinearization& lin_k,
                        const SpringLinearization& lin_d, const Matrix3X& u, double alpha,
                        double beta, Matrix3X& y, Matrix3X& buf);

/// diag += alpha diag(K) + beta diag(D), per particle and axis (3 by #P).
void add_jacobian_diagonal(const SpringSet& springs, const SpringLinearization& lin, double alpha,
                           double beta, Matrix3X& diag, Matrix3X& buf);

}  // namespace cloth
