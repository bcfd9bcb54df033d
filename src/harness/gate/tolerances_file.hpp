#pragma once
/// @file tolerances_file.hpp
/// A baseline's tolerances.toml, hand-written: how far each quantity of metrics.csv may move
/// ({ abs, rel } each, with its reason), which stability searches are gated ([stability]),
/// which quantities are not gated for an engine and why ([ungated.<engine>]), and which
/// engines' shapes are compared up to the scene's mirror image ([mirror]).

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
  // [mirror]: engines whose final shape is compared up to the scene's mirror image
  std::set<std::string> mirrored;
};

/// The quantities of metrics.csv, in the order they are gated.
extern const std::vector<std::string> kMetricQuantities;

/// Reads and checks a tolerance file. Throws UserError naming file, line and key for a file
/// that does not parse, an unknown key or quantity, a quantity without a tolerance, or a
/// tolerance that is not a finite number >= 0 (NaN included).
Tolerances read_tolerances(const std::filesystem::path& p);

}  // namespace clothbench
