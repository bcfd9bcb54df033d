#pragma once
/// @file accuracy_sweep.hpp
/// `clothbench accuracy`: how far each engine and integrator of a scenario lands from a fine
/// reference solution, what that costs, over a time-step sweep (work_precision.csv), the
/// fitted convergence order of each (convergence.csv), the cheapest configuration meeting an
/// error tolerance (recommendation.csv), and optionally the same question for grid
/// resolution (resolution.csv).
///
/// Files written into AccuracyOptions::out_dir (their columns: io/output_schema.cpp, printed
/// by `clothbench schema --outputs`):
///   scenario.toml                   the resolved scenario the sweep ran (checked by resume)
///   reference.csv                   the fine reference runs
///   work_precision.csv              one row per engine, integrator and dt
///   convergence.csv                 the fitted order of each engine and integrator
///   recommendation.csv              the cheapest row within the tolerance   (tolerance > 0)
///   resolution.csv                  one row per engine, integrator and grid   (resolutions)
///   resolution_recommendation.csv   the cheapest grid within the tolerance
///                                                              (resolutions, tolerance > 0)
///
/// "Cheapest" does not depend on the machine or on the other jobs running: within an engine
/// rows are ranked by counted_work (Bullet engines, whose work is not counted, by steps times
/// particles), then by error, then by row order. Overall, the engines' choices are compared
/// by counted_work when all are the custom engine's, otherwise by wall time per simulated
/// second, the one cost both kinds share (Bullet against the custom engine is a comparison
/// of machine time). The cost column holds counted_work (empty for Bullet engines).
/// Files of an earlier sweep in the folder that this one does not write are removed, so the
/// folder always describes one sweep.

#include <limits>
#include <string>
#include <vector>

#include "cloth/model/integrator.hpp"
#include "harness/engines/material_distance.hpp"
#include "harness/run/run_parallel.hpp"
#include "harness/scenario/scenario.hpp"
#include "harness/sweeps/accuracy_recommendation.hpp"
#include "harness/sweeps/accuracy_rows.hpp"
#include "harness/sweeps/accuracy_summary.hpp"
#include "harness/sweeps/convergence.hpp"
#include "harness/sweeps/shard.hpp"

namespace clothbench {

/// What to sweep and how.
struct AccuracyOptions {
  std::string out_dir;                         // where the CSV files go (created)
  std::vector<std::string> engines;            // engine names to sweep; empty: every engine
  std::vector<cloth::Integrator> integrators;  // custom engines only; empty: every integrator
  std::vector<double> dts;                     // s, explicit time steps; empty: halvings
  int halvings = 4;              // time steps per engine: dt, dt/2, ..., dt/2^(halvings-1)
                                 // from the engine's scenario dt
  double tolerance = -1;         // m, > 0: recommend the cheapest config within it
  double reference_dt = 0;       // s, > 0: the time-step study's rk4 reference step (at most
                                 // the smallest swept dt and a quarter of rk4's predicted
                                 // limit, dividing a frame); 0: chosen as below
  std::vector<int> resolutions;  // square grids r x r to compare; empty: none
  int repeats = 3;               // wall time is the median of this many runs
  int jobs = default_jobs();     // threads
  bool resume = false;           // keep the rows already in out_dir, run the rest
  bool progress = true;          // progress bar on stderr
  Shard shard;  // --shard K/N: only this share of the time-step study's rows (shard.hpp);
                // the fits and recommendations are left to the merged sweep
};

/// Runs the accuracy sweep of sc described by o and writes its files into o.out_dir.
///
/// Time-step sweep: every selected engine (custom engines: every selected integrator) at each
/// swept dt. The reference is the custom engine with rk4 at o.reference_dt when given, else
/// at the smallest swept dt / 4 (which
/// divides frame_interval whenever the swept dts do), or, where that is past a quarter of
/// rk4's predicted limit (implicit engines at large steps), the largest step within it that
/// divides frame_interval; its error floor is the RMS distance at
/// the final time between rk4 at twice the reference dt and the reference: about 15 times the
/// reference's own truncation error (rk4 at 2h errs 2^4 times more) and never below its
/// round-off, so rows whose error_final exceed it are fitted for order and others are not.
///
/// Resolution sweep: each r of o.resolutions re-parses the scenario with cloth.particles =
/// [r, r] and the same total mass; every configuration runs at its engine's scenario dt. The
/// reference is the finest grid with rk4 at the smallest dt of either study; errors compare
/// final shapes at common material points (see material_rms_distance). The rerun field of
/// resolution.csv holds a comma (cloth.particles=[r,r]) and is quoted.
///
/// Identical configurations (two engines differing in name only) run once. Rows are appended
/// and flushed as they finish and rewritten in a fixed order at the end, so the files do not
/// depend on o.jobs (apart from wall-time columns).
///
/// Throws UserError for bad options (an unknown engine, an "indices" constraint with
/// resolutions), an unwritable out_dir, a malformed file to resume or a resume against a
/// different sweep, or a reference that blows up; std::invalid_argument (kept for the tests
/// that expect it) for a dt that does not divide frame_interval.
AccuracyReport run_accuracy(const Scenario& sc, const AccuracyOptions& o);

}  // namespace clothbench
