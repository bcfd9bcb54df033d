#pragma once
/// @file shard.hpp
/// Sweeps split into shards for many machines (`--shard K/N` on stability, accuracy and map)
/// and joined again (`clothbench merge`).
///
/// A sweep is a list of independent units (a stability search, an accuracy row, a map point);
/// shard K of N computes the units whose index i in the whole sweep's order has i mod N = K - 1
/// (a fixed split that needs no coordination), into its own folder, with shard.toml beside its
/// files:
///   command, shard, shards   which sweep and which share of it
///   version, git_commit      the clothbench that ran it (merge refuses a mix)
///   table, sidecars          the sweep's result CSV and the files naming its scenario and
///                            options (merge requires them to be identical in every shard)
///   unit_columns, key_columns  a row's unit is its first unit_columns fields, its key its first
///                            key_columns fields
///   units                    every unit of the whole sweep, in order

#include <string>
#include <vector>

namespace clothbench {

/// Which share of a sweep to compute: shard index of count (count 0: the whole sweep).
struct Shard {
  int index = 0;  // 1..count
  int count = 0;  // 0: not sharded
  bool sharded() const { return count > 0; }
  /// True when unit number i (0-based, in the sweep's order) belongs to this shard.
  bool owns(size_t i) const { return !sharded() || int(i % size_t(count)) == index - 1; }
  /// "K/N".
  std::string text() const;
};

/// Parses "K/N" (whole numbers, 1 <= K <= N <= 100000); throws UserError naming --shard.
Shard parse_shard(const std::string& text);

/// What shard.toml records about the whole sweep.
struct ShardPlan {
  std::string command;                // stability, map, accuracy
  std::string table;                  // result CSV, e.g. stability.csv
  std::vector<std::string> sidecars;  // files naming the scenario, options and references,
                                      // e.g. stability_scenario.toml
  int unit_columns = 0, key_columns = 0;
  std::vector<std::string> units;  // every unit's key (its fields joined as CSV), in order
};

/// The name of the shard file in a shard's folder.
extern const char* const kShardFile;

/// Records shard s of plan p in dir (ending in '/'). With resume, refuses a folder that holds
/// another shard or sweep (or a sharded one when s is not sharded). An unsharded sweep removes
/// a shard.toml left by an earlier sweep in the folder. Throws UserError naming the file.
void record_shard(const std::string& dir, const Shard& s, const ShardPlan& p, bool resume);

/// The key of a unit or row: fields [0, count) joined as CSV fields.
std::string join_fields(const std::vector<std::string>& fields, size_t count);

/// What a merge did.
struct MergeSummary {
  std::string command, table;
  int shards = 0;
  size_t rows = 0;
};

/// Joins the shard folders dirs of one sweep into out_dir: the table with every row in the
/// unsharded sweep's order, its sidecars and run.json. Throws UserError (naming the folders,
/// files and lines) when a folder is not a shard, the shards belong to different sweeps
/// (command, shard count, version, scenario or options), a shard is missing or given twice,
/// or a row is missing, doubled or in the wrong shard.
MergeSummary merge_shards(const std::string& out_dir, const std::vector<std::string>& dirs);

}  // namespace clothbench
