#pragma once
/// @file runner.hpp
/// Runs every engine of a scenario on exactly its scene and writes the CSV files.

#include <atomic>
#include <limits>
#include <string>
#include <vector>

#include "cloth/model/model.hpp"
#include "cloth/model/simulator.hpp"
#include "harness/fabric/standard_overhang.hpp"
#include "harness/run/metrics.hpp"
#include "harness/run/progress.hpp"
#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// What one engine did over the scenario.
struct EngineRun {
  EngineSpec spec;
  std::vector<FrameMetrics> frames;        // one per logged frame, the last one unstable
                                           // when the run blew up
  std::vector<cloth::Matrix3X> positions;  // 3 by #P per frame (when kept)
  std::vector<double> snapshot_times;      // s
  std::vector<cloth::Matrix3X> snapshots;  // 3 by #P at those times
  cloth::Counters counters;
  double wall_s = 0;       // s spent in step() alone
  bool stable = true;      // false after a blow-up or a timeout
  bool timed_out = false;  // stopped after Scenario::max_run_seconds (stable is false,
                           // blowup_t NaN)
  double blowup_t = std::numeric_limits<double>::quiet_NaN();  // s, first unstable step
  double max_energy_error = 0;  // J, largest |energy_error| while stable
  std::string cause;  // why the run became unstable: non-finite, strain or energy ("" if stable)
  double final_kinetic = 0;          // J, kinetic energy of the last logged state
  double final_static_residual = 0;  // static_residual() of the last logged state
};

/// Run-wide options.
struct RunOptions {
  std::vector<std::string> engines;    // names to run; empty: all (the reference always runs)
  bool progress = true;                // progress on stderr
  bool keep_positions = true;          // keep every frame's positions (for divergence)
  int member = 0;                      // ensemble member: 0 the scene, m >= 1 perturbed
  unsigned long long member_seed = 0;  // seed of the members' perturbations
};

/// All engines of one scenario, and their divergence from the reference.
struct RunResult {
  Scenario scenario;
  cloth::Model model;  // the scene every metric is measured in
  std::vector<EngineRun> runs;
  int reference = 0;                                // index into runs
  std::vector<std::vector<Divergence>> divergence;  // per run, per common frame
  std::vector<OverhangSequence> overhangs;          // per run, the cantilever standard's sequence
                                            // ([test] overhang_rule = "standard"; else empty)
};

/// Set from a signal handler to stop a run at the next frame (Interrupted is thrown).
std::atomic<bool>& interrupt_requested();

/// Thrown when interrupt_requested() stops a run.
struct Interrupted : std::runtime_error {
  Interrupted() : std::runtime_error("interrupted") {}
};

/// Runs one engine of sc over the scenario's duration, logging a frame every frame_interval.
/// Stops at the first step where a coordinate is not finite or a structural or shear spring's
/// stretch l / l0 - 1 > blowup_strain (bend springs and compression left out: a fold is no
/// blow-up), or
/// at the first energy check (every frame, and at least every kEnergyCheckInterval of
/// simulated time) where the energy error exceeds blowup_energy times the EnergyScale, or
/// once the run has taken sc.max_run_seconds of wall clock (when > 0): a timeout. model is the
/// scene's; an engine with its own scene (EngineSpec::scene, from its overrides) runs and is
/// measured in that scene's model instead.
EngineRun run_engine(const Scenario& sc, const EngineSpec& spec, const cloth::Model& model,
                     Progress* progress, bool keep_positions);

/// Longest simulated time (s) between two energy checks of a run: a stability trial is one
/// frame long, and a blow-up that grows and then decays within it must still be seen.
constexpr double kEnergyCheckInterval = 0.01;

/// Runs the scenario's engines (all engines are built first, so a bad one fails before any
/// work), on the scene of ensemble member options.member (ensemble_member.hpp; the result's
/// scenario and model are that member's), then with [test] overhang_rule = "standard" each
/// engine's sequence of overhangs (overhang_sequence.hpp). Throws std::invalid_argument for an
/// engine filter naming no engine.
RunResult run_scenario(const Scenario& sc, const RunOptions& options);

/// Writes frames.csv, divergence.csv, snapshots.csv, summary.csv, scenario.toml and run.json
/// into dir (created if needed), all at once: they are written into a hidden sibling that
/// takes the folder's place in one rename (StagedFolder); other files of dir stay.
void write_run(const RunResult& result, const std::string& dir);

/// Total steps of one engine over the scenario (for progress).
long long planned_steps(const Scenario& sc, const EngineSpec& spec);

/// RMS distance of engine i from the reference at their last common frame; NaN (undefined,
/// written empty) when there is none or when the reference did not run the whole scenario
/// (it blew up or timed out: its last frame is not the scene's end).
double final_divergence(const RunResult& result, size_t i);

/// Drape coefficient of the final frame of run, NaN when the scene has no support.
double final_drape_coefficient(const RunResult& result, const EngineRun& run);

/// Contents of run.json: tool version, git commit, compiler, date, and the facts about engine
/// kinds (has_integrators, energy_gated, energy_note) and integrators (order,
/// force_evals_per_step) that the report reads instead of keeping copies of its own; members
/// (JSON members, each line ending ",\n") go before the facts.
std::string run_info_json(const std::string& members = "");

/// Writes run_info_json() to dir/run.json atomically (sweep folders; dir ends with '/'),
/// unless dir holds a run (frames.csv) with its run.json, which stays.
void write_run_info(const std::string& dir);

}  // namespace clothbench
