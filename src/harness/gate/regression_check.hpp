#pragma once
/// @file regression_check.hpp
/// `clothbench check`: rerun shipped scenarios and compare them with recorded baselines, so a
/// change to the engine that moves a result shows up as a failing gate.
///
/// A scenario's baseline folder (reference/baselines/<scenario name>/) holds
///   tolerances.toml  hand-written: how far each quantity may move, each with its reason
///   metrics.csv      per-engine summary figures and costs
///   shape.csv        the final shape of every engine
///   stability.csv    the stability limits (when tolerances.toml has a [stability] table)
///   metrics_ensemble.csv  the members' values of the quantities gated by an ensemble (when it
///                    has [ensemble.<engine>] tables; ensemble_gate.hpp)
///   tests.csv        every engine's [test] metrics (when the scenario has a [test]), gated
///                    by tolerances.toml's [tests] table (test_metrics_gate.hpp)
/// (their columns: io/output_schema.cpp, printed by `clothbench schema --outputs`)
///
/// Every engine, stability and test metric row on either side is gated: one recorded in the
/// baseline that did not run (or was not measured) now fails, and so does one that ran without
/// a baseline.

#include <memory>
#include <string>
#include <vector>

#include "harness/io/csv_writer.hpp"
#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// The baseline files of `check --update`, each written in full to a temporary file before
/// any replaces its predecessor; commit() makes them all appear (and removes the ones no
/// longer recorded), so an update that fails or is interrupted changes no baseline.
class PendingBaselines {
 public:
  void add(std::unique_ptr<CsvWriter> file) { m_files.push_back(std::move(file)); }
  void remove_on_commit(const std::string& path) { m_removals.push_back(path); }
  /// Renames every file onto its target, then removes what remove_on_commit named.
  void commit();

 private:
  std::vector<std::unique_ptr<CsvWriter>> m_files;
  std::vector<std::string> m_removals;
};

/// How to check.
struct CheckOptions {
  std::string baseline_dir;            // folder holding one subfolder per scenario
  std::vector<std::string> overrides;  // --set overrides applied to every scenario
  bool update = false;                 // record new baselines instead of comparing
  bool record_perturbed = false;       // with update and overrides: record them anyway
  bool progress = true;
  int jobs = 1;                          // threads for the stability searches and ensembles
  bool ensemble = false;                 // run the ensembles and gate their rows (without it
                                         // they are shown, not gated; --update always runs them;
                                         // the command line's default is true)
  unsigned long long ensemble_seed = 0;  // seed of the members' perturbations (0: the
                                         // recorded members)
  double max_run_seconds = 0;            // s per engine run before it stops as a timeout (0: none)
  PendingBaselines* pending = nullptr;   // update: the new files wait here for the caller's
                                         // commit (nullptr: each scenario commits its own)
};

/// One gated quantity.
struct Gate {
  std::string scenario;
  std::string engine;    // engine name, or engine/integrator for stability limits
  std::string quantity;  // final_shape_rms, max_energy_error, stable_dt, engine, ...
  double baseline = 0;
  double now = 0;
  double difference = 0;  // |now - baseline| (final_shape_rms: the distance itself)
  double allowed = 0;     // largest difference that passes
  bool pass = true;
  std::string note;          // why it failed, why it is not gated, or what changed (--update)
  std::string allowed_text;  // shown instead of allowed when set (stability brackets)
  bool gated = true;         // false: shown for the record, with the reason in note
};

/// The note of a row gated by its ensemble when the ensembles did not run (--no-ensemble).
inline constexpr const char* kEnsembleElsewhere = "gated by its ensemble, not run (--no-ensemble)";

/// Checks (or with update, records) one scenario file against its baseline folder.
/// Throws std::invalid_argument for update with overrides unless record_perturbed is set (a
/// perturbed baseline recorded by accident would hide the very change it should catch),
/// ScenarioError for a bad scenario and UserError for a missing or malformed baseline (naming
/// the file, and for a CSV the line and column).
std::vector<Gate> check_scenario(const std::string& scenario_path, const CheckOptions& o);

/// The gate table as printed by `clothbench check` (one line per gate, aligned columns).
std::string format_gates(const std::vector<Gate>& gates);

/// A new, empty folder of its own under the system's temporary folder (TMPDIR), removed with
/// everything in it when the object goes, also when an exception passes: concurrent checks
/// of the same scenario (ctest -j) never share or delete each other's files.
class ScratchFolder {
 public:
  /// Creates <temporary folder>/<prefix>XXXXXX; throws UserError naming it on failure.
  explicit ScratchFolder(const std::string& prefix);
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const std::string& path() const { return m_path; }

 private:
  std::string m_path;
};

}  // namespace clothbench
