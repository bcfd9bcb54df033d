#pragma once
/// @file element_distance.hpp
/// Euclidean distances between mesh elements: point-segment, point-triangle, segment-segment.
///
/// Each is the minimum over the elements' closed point sets. The minimiser is either interior
/// (the projection onto the triangle's plane, or the common perpendicular of two segments) or on
/// the boundary, where the problem reduces to point-segment distances; every candidate is the
/// distance of an actual pair of points, so degenerate inputs (a collapsed triangle, a
/// zero-length or parallel segment) give the right value and never NaN for finite input.

#include "cloth/model/types.hpp"

namespace cloth {

/// Distance (m) from point p to the segment [a, b] (a point when a == b).
double point_segment_distance(const Vector3& p, const Vector3& a, const Vector3& b);

/// Distance (m) from point p to the closed triangle (a, b, c), collapsed ones included.
double point_triangle_distance(const Vector3& p, const Vector3& a, const Vector3& b,
                               const Vector3& c);

/// Distance (m) between the segments [p0, p1] and [q0, q1], parallel or collapsed ones included.
double segment_segment_distance(const Vector3& p0, const Vector3& p1, const Vector3& q0,
                                const Vector3& q1);

}  // namespace cloth
