#pragma once
/// @file accuracy_sweep.hpp
/// `clothbench accuracy`: how far each engine and integrator of a scenario lands from a fine
/// reference solution, what that costs, over a time-step sweep (work_precision.csv), the
/// fitted convergence order of each (convergence.csv), the cheapest configuration meeting an
/// error tolerance (recommendation.csv), and optionally the same question for grid
/// resolution (resolution.csv).
///
/// Files written into AccuracyOptions::out_dir:
///   scenario.toml                   the resolved scenario the sweep ran (checked by resume)
///   reference.csv                   study,engine,integrator,dt,particles,error_floor,rerun
///   work_precision.csv              engine,integrator,dt,stable,error_final,error_max,wall_s,
///                                   wall_s_per_sim_s,force_evals,cg_iterations,rerun
///   convergence.csv                 engine,integrator,order,points
///   recommendation.csv              scope,engine,integrator,dt,error_max,wall_s_per_sim_s,
///                                   tolerance,cost                         (tolerance > 0)
///   resolution.csv                  engine,integrator,particles,dt,stable,error_final,
///                                   wall_s_per_sim_s,force_evals,cg_iterations,rerun
///                                                                          (resolutions)
///   resolution_recommendation.csv   scope,engine,integrator,particles,dt,error_final,
///                                   wall_s_per_sim_s,tolerance,cost
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

#include "cloth/types.hpp"
#include "harness/scenario.hpp"
#include "harness/sweep.hpp"

namespace clothbench {

/// What to sweep and how.
struct AccuracyOptions {
  std::string out_dir;                   // where the CSV files go (created)
  std::vector<std::string> engines;      // engine names to sweep; empty: every engine
  std::vector<std::string> integrators;  // custom engines only; empty: every integrator
  std::vector<double> dts;               // s, explicit time steps; empty: halvings
  int halvings = 4;                      // time steps per engine: dt, dt/2, ..., dt/2^(halvings-1)
                                         // from the engine's scenario dt
  double tolerance = -1;                 // m, > 0: recommend the cheapest config within it
  std::vector<int> resolutions;          // square grids r x r to compare; empty: none
  int repeats = 3;                       // wall time is the median of this many runs
  int jobs = default_jobs();             // threads
  bool resume = false;                   // keep the rows already in out_dir, run the rest
  bool progress = true;                  // progress bar on stderr
};

/// One row of work_precision.csv or resolution.csv, as read back from the file.
struct AccuracyRow {
  std::string engine;
  std::string integrator;  // custom engines; "" for Bullet engines
  int particles = 0;       // #P of the grid it ran on
  double dt = 0;           // s
  bool stable = false;
  double error_final = std::numeric_limits<double>::infinity();  // m, RMS distance to the
                                                                 // reference at the final time
  double error_max = std::numeric_limits<double>::infinity();    // m, largest over the logged
                                                                 // frames (time-step sweep)
  double wall_s = 0;            // s in step(), median of the repeats (time-step sweep)
  double wall_s_per_sim_s = 0;  // s of wall time per simulated second
  long long force_evals = 0;
  long long cg_iterations = 0;  // time-step sweep
  std::string rerun;            // --set overrides that rerun the row with `clothbench run`
};

/// The solution errors are measured against.
struct AccuracyReference {
  std::string study;   // "dt" or "resolution"
  std::string engine;  // custom engine whose solver options it uses ("" when the scenario
                       // has none: the default options)
  double dt = 0;       // s, rk4 time step
  int nu = 0, nv = 0;  // grid
  double error_floor = std::numeric_limits<double>::quiet_NaN();  // m, see below; NaN: not
                                                                  // measured
  std::string description;                                        // one line naming it
};

/// Fitted order of one engine/integrator over the time-step sweep.
struct ConvergenceFit {
  std::string engine;
  std::string integrator;                                   // "" for Bullet engines
  double order = std::numeric_limits<double>::quiet_NaN();  // NaN: fewer than 2 points
  int points = 0;  // stable rows with error_final above the reference's error floor
};

/// The cheapest configuration within the tolerance, for one engine or overall.
struct Recommendation {
  std::string scope;   // "engine" or "overall"
  std::string engine;  // scope "engine": the engine; "overall": the winner's ("" when none)
  bool found = false;  // false: no stable row of the scope meets the tolerance
  AccuracyRow row;     // found: the cheapest; otherwise the most accurate stable row (if any)
};

/// Everything run_accuracy measured, in the files' row order.
struct AccuracyReport {
  AccuracyReference reference;
  std::vector<AccuracyRow> rows;  // work_precision.csv
  std::vector<ConvergenceFit> convergence;
  double tolerance = -1;                        // m, as given
  std::vector<Recommendation> recommendations;  // per engine, then overall (tolerance > 0)
  AccuracyReference resolution_reference;       // study empty when no resolutions
  std::vector<AccuracyRow> resolution_rows;     // resolution.csv
  std::vector<Recommendation> resolution_recommendations;  // (resolutions, tolerance > 0)
  int runs = 0;     // configurations run by this call (identical ones once; references not
                    // counted)
  int resumed = 0;  // rows kept from an earlier sweep (resume)
  std::vector<std::string> files;  // paths written
};

/// A CG iteration's cost in force evaluations, with its share of the Newton iteration that
/// linearises the springs for it: implicit-Euler steps on the flag and the table (release
/// build, one job, median of three runs, dt = 0.2, 0.1 and 0.05 ms) cost 3.0 to 3.6 explicit
/// force evaluations per CG iteration beyond their one force evaluation.
constexpr double kCgIterationCost = 3.0;

/// The machine-independent cost of a custom-engine row in particle force evaluations:
/// (force_evals + kCgIterationCost * cg_iterations) * particles; NaN for a Bullet row (its
/// work is not counted).
double counted_work(const AccuracyRow& r);

/// Runs the accuracy sweep of sc described by o and writes its files into o.out_dir.
///
/// Time-step sweep: every selected engine (custom engines: every selected integrator) at each
/// swept dt. The reference is the custom engine with rk4 at the smallest swept dt / 4 (which
/// divides frame_interval whenever the swept dts do); its error floor is the RMS distance at
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
/// Throws std::invalid_argument for bad options (an unknown engine or integrator, a dt that
/// does not divide frame_interval, an "indices" constraint with resolutions), and
/// std::runtime_error for an unwritable out_dir, a resume against a different sweep, or a
/// reference that blows up.
AccuracyReport run_accuracy(const Scenario& sc, const AccuracyOptions& o);

/// A short text summary for stdout: the references, each configuration's fitted order and
/// best error, and the recommendations (saying so when nothing meets the tolerance).
std::string accuracy_summary(const AccuracyReport& report);

/// Least-squares slope of log(error) against log(dt); NaN for fewer than two points.
double fitted_order(const std::vector<double>& dts, const std::vector<double>& errors);

/// Position at material coordinates (u, v) in [0, 1]^2 of a grid, by bilinear interpolation.
/// @param x   3 by #P positions of an nu by nv grid (p = j * nu + i, u = i / (nu - 1))
cloth::Vector3 bilinear_position(const cloth::Matrix3X& x, int nu, int nv, double u, double v);

/// RMS over the particles of grid a of the distance to grid b at the same material point.
/// @param a  3 by #P positions of an a_nu by a_nv grid
/// @param b  3 by #P positions of a b_nu by b_nv grid, interpolated bilinearly
double material_rms_distance(const cloth::Matrix3X& a, int a_nu, int a_nv, const cloth::Matrix3X& b,
                             int b_nu, int b_nv);

}  // namespace clothbench
