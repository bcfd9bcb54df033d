#pragma once
/// @file exact_orient.hpp
/// The exact sign of the 3-D orientation determinant, for any finite doubles.
///
/// orient3d_sign(a, b, c, d) = sign det[b - a, c - a, d - a] (columns), which equals
/// sign ((b - a) x (c - a)) . (d - a): +1 when d lies on the side of the plane through a, b, c
/// that the right-hand normal of (a, b, c) points to, -1 on the other side, 0 when the four
/// points are coplanar. (Shewchuk's orient3d has the opposite sign.)
///
/// Three stages, after Shewchuk, "Adaptive precision floating-point arithmetic and fast robust
/// geometric predicates", Discrete Comput. Geom. 18 (1997):
///  1. a floating-point filter: the determinant in doubles, trusted when it exceeds an error
///     bound proportional to its permanent (and nothing overflowed);
///  2. otherwise (four points sharing a coordinate give 0 at once) the determinant as an exact
///     sum of products, split exactly into doubles with two-product (std::fma) and summed exactly
///     with two-sum into a nonoverlapping expansion whose largest part gives the sign: from the
///     differences b - a, c - a, d - a when they are exact in doubles (24 parts), else from the
///     24 triple products of the 4 by 4 cofactor expansion (96 parts). The inputs are first
///     scaled by a power of two so no product overflows or underflows;
///  3. when the inputs' exponents span too far for stage 2 (nonzero magnitudes more than 2^480
///     apart, only in blown-up states), exact integer arithmetic on the binary significands.
/// The file is compiled with -ffp-contract=off (src/cloth/CMakeLists.txt) so the filter and the
/// two-sum steps are evaluated as written; the two-products use std::fma explicitly.

#include "cloth/model/types.hpp"

namespace cloth {

/// Exact sign (-1, 0 or +1) of det[b - a, c - a, d - a] for finite a, b, c, d (m or any unit);
/// +1 when d is on the side of plane (a, b, c) that (b - a) x (c - a) points to.
int orient3d_sign(const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d);

/// The same sign from stage 3 alone (big integers on the exact significands), whatever the
/// inputs' range: the slow path orient3d_sign takes for widely spread exponents, exposed so
/// tests can check it on ordinary inputs too.
int orient3d_sign_wide(const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d);

}  // namespace cloth
