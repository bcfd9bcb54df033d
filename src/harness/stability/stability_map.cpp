/// @file stability_map.cpp

#include "harness/stability/stability_map.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>

#include "harness/io/csv_reader.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/text_file.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/progress.hpp"
#include "harness/run/run_parallel.hpp"
#include "harness/scenario/scenario_writer.hpp"
#include "harness/stability/stability_files.hpp"

namespace clothbench {
namespace {

constexpr const char* kMapSidecar = "map_scenario.toml";

/// One point to search: its values, its overrides and its scenario.
struct MapPoint {
  std::vector<std::string> values, overrides;
  Scenario scenario;
  std::string dir;  // its stability sweep's folder
};

/// The folder of point index i: points/0007.
std::string point_dir(const std::string& out_dir, size_t i) {
  char name[32];
  std::snprintf(name, sizeof name, "points/%04zu", i);
  return out_dir + "/" + name;
}

/// The shard's points (every point when not sharded), each with its scenario loaded, and the
/// record of the whole map for shard.toml.
std::vector<MapPoint> plan_points(const ScenarioAtPoint& load, const MapOptions& o,
                                  ShardPlan& plan) {
  const int keys = int(o.varied.size());
  plan = {"map", "map.csv", {kMapSidecar}, keys, keys + 2, {}};
  std::vector<MapPoint> points;
  const std::vector<GridPoint> grid = grid_points(o.varied);
  for (size_t i = 0; i < grid.size(); ++i) {
    MapPoint p;
    for (size_t k = 0; k < o.varied.size(); ++k) {
      p.values.push_back(o.varied[k].values[grid[i][k]]);
      p.overrides.push_back(o.varied[k].override_text(grid[i][k]));
    }
    plan.units.push_back(join_fields(p.values, p.values.size()));
    if (!o.shard.owns(i)) continue;
    p.scenario = load(p.overrides);
    p.dir = point_dir(o.out_dir, i);
    points.push_back(std::move(p));
  }
  return points;
}

/// What map_scenario.toml holds: the varied keys and search options, then the scenario.
std::string map_sidecar_text(const Scenario& base, const MapOptions& o) {
  std::string text =
      "# the stability map whose points points/ holds; --resume continues it only\n"
      "# with this scenario and these options:\n#  ";
  for (const VariedKey& k : o.varied) {
    text += " --vary " + k.key + "=";
    for (size_t i = 0; i < k.values.size(); ++i) text += (i ? "," : "") + k.values[i];
  }
  for (const std::string& e : o.search.engines) text += " -e " + e;
  for (cloth::Integrator i : o.search.integrators)
    text += " -i " + std::string(cloth::integrator_name(i));
  return text + "\n" + stability_sidecar_text(base, o.search);
}

/// Creates the folder and records the map; with resume, refuses a folder of another map.
void prepare_folder(const Scenario& base, const MapOptions& o, const ShardPlan& plan) {
  make_directories(o.out_dir);
  record_shard(o.out_dir + "/", o.shard, plan, o.search.resume);
  const std::string sidecar = o.out_dir + "/" + kMapSidecar;
  const std::string text = map_sidecar_text(base, o), earlier = read_text(sidecar);
  if (o.search.resume && !earlier.empty() && earlier != text)
    throw UserError(sidecar +
                    ": cannot resume: the folder holds a map of another scenario, "
                    "other --vary values or other options; run without --resume or choose "
                    "another output folder");
  AtomicFile f(sidecar);
  f.write(text);
  f.commit();
}

/// Runs one point's stability sweep in its own folder.
std::vector<StabilityRow> search_point(const MapPoint& p, const MapOptions& o, int jobs) {
  StabilityOptions s = o.search;
  s.out_dir = p.dir;
  s.jobs = jobs;
  s.progress = false;
  s.shard = Shard();
  return run_stability(p.scenario, s);
}

/// The rows map.csv already holds, by point (its values joined as in shard.toml's units):
/// what --resume keeps of a finished or merged map, whose points/ may be gone.
std::map<std::string, std::vector<StabilityRow>> kept_rows(const MapOptions& o) {
  std::map<std::string, std::vector<StabilityRow>> kept;
  const std::string path = o.out_dir + "/map.csv";
  const CsvTable table = read_csv_leniently(path);
  if (table.header != map_header(o.varied)) return kept;
  const auto source =
      std::make_shared<const CsvRecord::Source>(CsvRecord::Source{path, stability_header()});
  const size_t keys = o.varied.size();
  for (const CsvRecord& r : table.records) {
    if (r.size() != table.header.size()) continue;
    std::vector<std::string> fields(r.fields().begin() + long(keys), r.fields().end());
    kept[join_fields(r.fields(), keys)].push_back(
        stability_row(CsvRecord(source, r.line(), std::move(fields))));
  }
  return kept;
}

void write_map_csv(const MapOptions& o, const std::vector<MapRow>& rows) {
  CsvWriter csv(o.out_dir + "/map.csv", map_header(o.varied));
  for (const MapRow& r : rows) {
    // a value as written (a TOML string keeps its quotes), quoted for CSV as on stdout
    for (const std::string& v : r.values) csv.add(csv_field(v));
    for (const std::string& f : stability_fields(r.stability)) csv.add(f);
    csv.end_row();
  }
  csv.commit();
}

}  // namespace

std::vector<std::string> map_header(const std::vector<VariedKey>& varied) {
  std::vector<std::string> header;
  for (const VariedKey& k : varied) header.push_back(k.key);
  for (const std::string& c : stability_header()) header.push_back(c);
  return header;
}

std::vector<MapRow> run_map(const ScenarioAtPoint& load, const MapOptions& o) {
  // plan: every point's scenario first, so a value the scenario refuses stops before any run
  if (o.varied.empty() || o.varied.size() > 2)
    throw UserError("map: expected one or two --vary keys");
  ShardPlan plan;
  const std::vector<MapPoint> points = plan_points(load, o, plan);
  prepare_folder(load({}), o, plan);

  // search: points spread over the jobs, the rest of the jobs inside each point's search
  const int outer = std::max(1, std::min<int>(o.search.jobs, int(points.size())));
  const int inner = std::max(1, o.search.jobs / outer);
  Progress progress(double(points.size()), "points", o.search.progress);
  std::mutex progress_mutex;
  std::vector<std::vector<StabilityRow>> found(points.size());
  const auto kept = o.search.resume ? kept_rows(o) : decltype(kept_rows(o))();
  run_parallel(int(points.size()), outer, [&](int i) {
    const MapPoint& p = points[size_t(i)];
    // a point map.csv holds and whose own folder is gone (a merged map) is not searched again
    const auto k = kept.find(join_fields(p.values, p.values.size()));
    std::error_code ec;
    if (k != kept.end() && !std::filesystem::exists(p.dir + "/stability.csv", ec))
      found[size_t(i)] = k->second;
    else
      found[size_t(i)] = search_point(p, o, inner);
    std::string label;
    for (const std::string& s : p.overrides) label += (label.empty() ? "" : " ") + s;
    const std::lock_guard<std::mutex> hold(progress_mutex);
    progress.line("point done: " + label);
    progress.advance(1, label);
  });

  // report: one row per point, engine and integrator, in grid order
  std::vector<MapRow> rows;
  for (size_t i = 0; i < points.size(); ++i)
    for (const StabilityRow& r : found[i]) rows.push_back({points[i].values, r});
  write_map_csv(o, rows);
  return rows;
}

}  // namespace clothbench
