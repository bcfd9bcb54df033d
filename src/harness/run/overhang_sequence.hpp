#pragma once
/// @file overhang_sequence.hpp
/// The cantilever standard's sequence of overhangs run on one engine ([test] overhang_rule =
/// "standard"): each settle is a run of the scenario's duration with the held platform ending
/// at another column of the strip, measured as the cantilever test measures the scene's own.

#include <vector>

#include "harness/fabric/standard_overhang.hpp"
#include "harness/run/runner.hpp"

namespace clothbench {

/// The overhangs (m, increasing) the strip of model offers and each one's platform edge (m):
/// every column (the particles sharing a rest x within 1e-9 m) as the clamp, with at least
/// two columns held (the clamp stays level) and one beyond.
struct OverhangCandidates {
  std::vector<double> overhang;  // m
  std::vector<double> edge;      // m, rest x of the clamp column
};

/// The candidates of a strip along +x of rest positions x0 (3 by #P, m).
OverhangCandidates overhang_candidates(const cloth::Matrix3X& x0);

/// Runs the standard's search (find_standard_overhang) for run's engine on sc (the scene run
/// gave, model its model): the scene's own edge first, measured on run itself (no new run),
/// then one run of sc.duration per further overhang, the platform held on every axis up to
/// that column and nothing between it and the scene's edge held. A settle is measured at its
/// last frame and at nine tenths of the run (the positions kept per frame, else the last two
/// snapshots). Empty (no runs, NaN results) for a strip of fewer than three columns.
OverhangSequence standard_overhang_sequence(const Scenario& sc, const cloth::Model& model,
                                            const EngineRun& run);

}  // namespace clothbench
