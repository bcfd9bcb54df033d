#pragma once
/// @file standard_overhang.hpp
/// The cantilever standard's own rule (ASTM D1388 option A, BS 3356): the strip is pushed over
/// the platform's edge until its chord from the edge to the tip makes 41.5 degrees with the
/// horizontal, and the bending length is half that overhang, c = l / 2. A simulated strip's
/// held set is discrete, so the overhangs on offer are those of its columns: the search settles
/// the strip at one overhang after another until two neighbouring overhangs bracket 41.5
/// degrees, then interpolates the chord angle linearly between those two settled runs.

#include <cstddef>
#include <functional>
#include <vector>

#include "harness/fabric/test_metric.hpp"

namespace clothbench {

/// The standard's chord angle (deg): at it the heavy elastica has l / c = 2 within 0.03 %.
constexpr double kStandardChordAngle = 41.5;

/// Largest change (deg) of the chord angle over the last tenth of a settle for which it counts
/// as settled. Near 41.5 degrees the elastica's chord angle grows by 36 degrees per unit of
/// l / c, so 0.05 degrees is 0.07 % of the bending length.
constexpr double kSettledChordChange = 0.05;

/// One settled run of the sequence.
struct OverhangRun {
  double edge = 0;           // m, rest x of the last held column (the clamp)
  double overhang = 0;       // m, rest length from the clamp to the tip
  double chord_angle = 0;    // deg, at the run's end; NaN when the run blew up
  double settle_change = 0;  // deg, chord angle at the end minus at nine tenths of the run
  bool settled = false;      // stable and |settle_change| <= kSettledChordChange
  bool bracket = false;      // one of the two runs the result interpolates between
};

/// The sequence and what it found. overhang and bending_length are NaN when no two
/// neighbouring overhangs bracket 41.5 degrees (the strip is too short or too stiff, or too
/// limp at its shortest overhang), a run blew up, or a bracketing run did not settle.
struct OverhangSequence {
  std::vector<OverhangRun> runs;  // in the order they were settled
  double overhang = 0;            // m, l* where the chord angle reaches 41.5 degrees
  double bending_length = 0;      // m, l* / 2
};

/// Settles the strip with the clamp at candidate k (an index into the search's overhangs) and
/// measures it.
using SettleAt = std::function<OverhangRun(std::size_t k)>;

/// Finds the standard's overhang among overhangs (m, strictly increasing; the chord angle
/// grows with the overhang), settling first at first (an index into overhangs, e.g. the
/// scene's own, whose run may already exist). While the crossing lies on one side of the runs
/// so far, the next overhang is the heavy elastica's guess l = 2 c from the nearest run's
/// chord angle (elastica.hpp); once it is bracketed, the secant of the chord angle between the
/// bracket's ends; either clamped strictly inside the bracket, so each settle narrows it.
/// Stops when two neighbouring overhangs bracket 41.5 degrees, at a run that blew up, or when
/// the crossing lies beyond the candidates.
OverhangSequence find_standard_overhang(const std::vector<double>& overhangs, std::size_t first,
                                        const SettleAt& settle);

/// The rows of tests.csv for q, in the order written: standard_overhang (m),
/// bending_length_standard (m) and standard_settles (count, the settled runs it took).
std::vector<TestMetric> standard_rows(const OverhangSequence& q);

}  // namespace clothbench
