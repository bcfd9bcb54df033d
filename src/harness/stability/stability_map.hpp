#pragma once
/// @file stability_map.hpp
/// `clothbench map`: the stability search (stability_sweep) at every point of a grid of one or
/// two varied scenario keys, so the largest stable dt of each engine and integrator, measured
/// and predicted, can be read over a family of scenes.
///
/// Files written into MapOptions::out_dir:
///   map.csv             the varied keys' values, then the columns of stability.csv, one row
///                       per point, engine and integrator (written when every point is done)
///   map_scenario.toml   the varied keys, the search options and the scenario (checked by
///                       --resume)
///   shard.toml          with --shard: which share of the points (shard.hpp)
///   points/NNNN/        the stability sweep of point NNNN (its stability.csv and sidecar), so
///                       an interrupted map resumes point by point and row by row

#include <functional>
#include <string>
#include <vector>

#include "harness/scenario/scenario.hpp"
#include "harness/stability/stability_sweep.hpp"
#include "harness/sweeps/map_grid.hpp"

namespace clothbench {

/// Options of a map.
struct MapOptions {
  std::string out_dir;            // map.csv goes here (created)
  std::vector<VariedKey> varied;  // one or two keys
  StabilityOptions search;        // engines, integrators, dt_max, rel_tol, jobs, resume,
                                  // progress; its out_dir and shard are set per point
  Shard shard;                    // --shard K/N: only this share of the points (shard.hpp)
};

/// One row of map.csv: the point's values and one stability row.
struct MapRow {
  std::vector<std::string> values;  // one per varied key
  StabilityRow stability;
};

/// Loads the scenario with the given extra --set overrides (after the user's own).
using ScenarioAtPoint = std::function<Scenario(const std::vector<std::string>& overrides)>;

/// The columns of map.csv: the varied keys, then stability_header().
std::vector<std::string> map_header(const std::vector<VariedKey>& varied);

/// Loads every point's scenario first (a value the scenario refuses stops the map before any
/// run, naming the override), then runs the stability search of each point not done yet,
/// points spread over the jobs. Throws UserError for bad options, an unwritable folder or a
/// resume of another map.
std::vector<MapRow> run_map(const ScenarioAtPoint& load, const MapOptions& o);

}  // namespace clothbench
