#pragma once
/// @file drape_metrics.hpp
/// The Cusick drape test's shape metrics (BS 5058, ISO 9073-9) measured on a settled specimen:
/// its projected outline seen along gravity, as a radius against the angle around the support's
/// axis, and the number of folds that outline has.

#include <vector>

#include "cloth/model/types.hpp"
#include "harness/fabric/test_metric.hpp"

namespace clothbench {

/// Bins of the projected radius profile: one per degree.
inline constexpr int kDrapeProfileBins = 360;

/// The arc over which the profile is smoothed before its folds are counted (degrees), the
/// issue's definition of a fold.
inline constexpr double kFoldSmoothingDegrees = 10.0;

/// How far, as a fraction of the mean radius, a fold's tip must stand above the troughs beside
/// it. Smoothing alone does not make the outline of a flat disk meshed with M edges round its
/// rim free of maxima: the rim's chords dip by 1 - cos(pi / M) of the radius (0.05 % for 96
/// edges) every 360 / M degrees, and a 10 degree average leaves a ripple of that order. A draped
/// fold stands 10 to 40 % of the radius proud; 1 % separates the two by a wide margin.
inline constexpr double kFoldProminence = 0.01;

/// The settled specimen's outline around the support's axis.
struct DrapeProfile {
  std::vector<double> radius;  // kDrapeProfileBins, m: the largest projected distance from the
                               // axis of any point of the cloth's edges at angles in
                               // [k, k + 1) degrees around it
};

/// The outline of a cloth seen along gravity around the vertical line through axis_point.
/// Every edge of every triangle is sampled finely enough that each degree holds a sample at the
/// cloth's outline (bins no sample reaches are filled by interpolating their neighbours).
/// @param x  3 by #P positions (m)
/// @param triangles  the cloth's surface
/// @param axis_point  a point of the support's axis (m)
/// @param gravity  gravitational acceleration (m/s^2), non-zero: the axis's direction
DrapeProfile drape_profile(const cloth::Matrix3X& x, const std::vector<cloth::Triangle>& triangles,
                           const cloth::Vector3& axis_point, const cloth::Vector3& gravity);

/// The profile averaged over a centred arc of width degrees (circularly).
std::vector<double> smoothed_profile(const std::vector<double>& radius, double degrees);

/// The number of local maxima of a circular sequence that stand more than min_prominence above
/// the troughs on either side of them (counted by hysteresis from the lowest value round the
/// circle); a plateau counts once, and a constant sequence has none. With 0 it counts every
/// maximum.
int count_local_maxima(const std::vector<double>& values, double min_prominence = 0.0);

/// The prominence a fold's tip needs: kFoldProminence of the smoothed profile's mean radius.
double fold_prominence(const std::vector<double>& smooth);

/// The number of folds: local maxima of the profile after smoothing over kFoldSmoothingDegrees
/// that stand at least fold_prominence above the troughs beside them.
int drape_folds(const DrapeProfile& profile);

/// The rows of tests.csv for a settled drape: drape_coefficient (1), folds (1), and the smoothed
/// profile's min_radius and max_radius (m).
/// @param drape_coefficient  (shadow - support) / (specimen - support), computed by the caller
std::vector<TestMetric> drape_rows(const DrapeProfile& profile, double drape_coefficient);

}  // namespace clothbench
