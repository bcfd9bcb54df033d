#pragma once
/// @file tolerances_file.hpp
/// A baseline's tolerances.toml, hand-written: how far each quantity of metrics.csv may move
/// ({ abs, rel } each, with its reason), which stability searches are gated ([stability]),
/// which quantities are not gated for an engine and why ([ungated.<engine>]), which are gated
/// by an ensemble ([ensemble.<engine>]), which engines' shapes are compared up to the
/// scene's mirror image ([mirror]), and how far each metric of the scenario's textile standard
/// test (tests.csv) may move ([tests], test_metrics_gate.hpp):
///
///   [tests]
///   bending_length = { rel = 1e-9 }  # with the measured reason above it, as every line
///
/// A scenario with a [test] needs a line for every metric its tests.csv has; [ungated.<engine>]
/// may list a test metric as "test.<metric>".
///
/// An engine whose result on a chaotic scene no single run reproduces is gated by the
/// distribution of its results instead:
///
///   [ensemble.bullet-softbody-matched]
///   detect = { final_shape_rms = 0.001, final_com_y = 0.001 }  # shifts to catch (units of
///                                    # the quantity), or members = N (N >= 2) fixed
///   max_seconds = 60                 # with detect: s of member runs N may cost (default 60)
///   quantities = ["final_shape_rms", "final_com_y"]
///   reason = "a 1e-13 change of gravity moves its final shape by 16 mm"
///
/// The members: member 0 the scene, 1..N-1 perturbed at round-off level
/// (run/ensemble_member.hpp). With detect, `check --update` chooses N from the members'
/// measured spread (ensemble_runs.hpp, ensemble_size.hpp) and records it; with members = N it
/// runs N. `check --update` records the N members' values (metrics_ensemble.csv); `check`
/// runs the same N members and gates each listed quantity's mean against the recorded mean by
/// Welch's t-test at false-alarm rate 1e-3 per quantity, Bonferroni-divided over the
/// scenario's ensemble rows (ensemble_gate.hpp). final_shape_rms is, per member, the RMS
/// distance of its final shape from the recorded shape.csv (member 0's). With --no-ensemble
/// these rows are shown, not gated. A quantity is either listed here or in [ungated.<engine>]
/// or gated by its tolerance, never two of these.

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "cloth/model/integrator.hpp"

namespace clothbench {

/// allowed difference: abs + rel * |baseline|
struct Tolerance {
  double abs = 0;
  double rel = 0;
  double allowed(double baseline) const { return abs + rel * std::abs(baseline); }
};

struct Tolerances {
  std::map<std::string, Tolerance> quantity;  // by quantity name
  bool stability = false;
  std::string stability_engine;
  std::vector<cloth::Integrator> stability_integrators;  // empty: every integrator
  double stability_rel_tol = 0.02;
  bool stability_adjacent = false;  // brackets that only share an end pass too
  // [ungated.<engine>]: quantities not gated for that engine, with the reason
  std::map<std::string, std::map<std::string, std::string>> ungated;
  // [ensemble.<engine>]: members and quantities gated by the ensemble, with the reason
  struct Ensemble {
    int members = 0;  // N >= 2 (members = N), or 0: chosen by check --update from detect
    std::set<std::string> quantities;
    std::string reason;
    // detect = { quantity = shift }: the shift of each quantity's mean (its unit) the gate is
    // to catch with probability kEnsemblePower (ensemble_size.hpp)
    std::map<std::string, double> detect;
    double max_seconds = 60;  // s of member runs (one core) the chosen ensemble may cost
  };
  std::map<std::string, Ensemble> ensemble;
  // [mirror]: engines whose final shape is compared up to the scene's mirror image
  std::set<std::string> mirrored;
  // [tests]: how far each metric of tests.csv may move, by metric name
  std::map<std::string, Tolerance> tests;
};

/// The quantities of metrics.csv, in the order they are gated.
extern const std::vector<std::string> kMetricQuantities;

/// Reads and checks a tolerance file. Throws UserError naming file, line and key for a file
/// that does not parse, an unknown key or quantity, a quantity without a tolerance, or a
/// tolerance that is not a finite number >= 0 (NaN included), an ensemble of fewer than 2
/// members or whose members is not a whole number, and a quantity both in an ensemble and
/// ungated.
Tolerances read_tolerances(const std::filesystem::path& p);

}  // namespace clothbench
