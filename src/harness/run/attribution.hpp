#pragma once
/// @file attribution.hpp
/// `clothbench run --explain`: why a Bullet engine differs from the reference. For each
/// Bullet engine the run adds the custom engine with Bullet's time scheme and dt (the matched
/// engine), and splits the Bullet engine's distance from the reference into
///   scheme = reference vs matched engine (the time scheme and dt alone, in our model) and
///   model  = matched engine vs Bullet engine (one scheme, two models: contact, parameters).
/// bullet-softbody (position-based dynamics) has no matched custom scheme and says so.

#include <optional>
#include <string>
#include <vector>

#include "harness/run/runner.hpp"
#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// The name of the matched engine --explain adds for the Bullet engine bullet_name.
std::string matched_engine_name(const std::string& bullet_name);

/// The custom engine with bullet's time scheme and dt, or nullopt when there is none
/// (bullet-softbody): imex-euler for bullet-deformable's explicit mode; for its implicit mode
/// implicit-euler with one linearised Newton solve and no clamp (Bullet's defaults:
/// m_maxNewtonIterations = 1, the full spring Jacobian), or one line-search Newton
/// iteration when Bullet's line_search is on.
std::optional<EngineSpec> matched_engine(const EngineSpec& bullet);

/// Adds the matched engine of every Bullet engine of sc that names selects (empty: all), unless
/// sc holds it already (a scenario.toml written by --explain); appends the matched names to
/// names when it is not empty, so that an -e filter keeps them. Throws UserError when the name
/// is taken by an engine of another kind, dt or integrator.
void add_matched_engines(Scenario& sc, std::vector<std::string>& names);

/// One row of attribution.csv.
struct AttributionRow {
  std::string engine;     // the Bullet engine
  std::string reference;  // the run's reference engine
  std::string matched;    // the matched custom engine ("" for bullet-softbody)
  std::string at;         // "final" (last common frame) or "max" (largest over the frames)
  double t = 0;           // s, the frame of "final"; of "max", the last frame compared
  double total_rms = 0;   // m, Bullet engine vs reference
  double scheme_rms = 0;  // m, matched engine vs reference (NaN: no matched scheme)
  double model_rms = 0;   // m, matched engine vs Bullet engine (NaN: no matched scheme)
  std::string note;       // why a row has no split, or where it stops short of the end
};

/// The rows of every Bullet engine of result (two each: final and max).
std::vector<AttributionRow> attribution(const RunResult& result);

/// Writes attribution(result) to dir/attribution.csv atomically.
void write_attribution(const RunResult& result, const std::string& dir);

}  // namespace clothbench
