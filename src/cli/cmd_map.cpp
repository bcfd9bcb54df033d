/// @file cmd_map.cpp
/// `clothbench map`: the stability search over a grid of one or two varied scenario keys.

#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/io/output_lock.hpp"
#include "harness/io/user_error.hpp"
#include "harness/scenario/scenario_overrides.hpp"
#include "harness/stability/stability_map.hpp"
#include "support/option_checks.hpp"
#include "support/scenario_input.hpp"
#include "support/summaries.hpp"

namespace clothbench::cli {
namespace {

struct MapArgs {
  std::string scenario_path;           // empty: the embedded seed scene
  std::vector<std::string> overrides;  // --set KEY=VALUE
  std::vector<std::string> vary;       // --vary KEY=LIST_OR_RANGE
  bool quiet = false;
  double max_run_seconds = 0;  // s, 0: no limit
  MapOptions options;          // out_dir empty: out/<scenario name>-map
};

/// The key of a --set KEY=VALUE (the text before the first '=').
std::string override_key(const std::string& text) {
  return text.substr(0, text.find('='));
}

/// Why the map cannot vary key, "" when it can: a key the search sets at every point itself
/// (an engine's dt or integrator, the frame interval, the name), or an engine's key that -e
/// leaves out; either would give identical rows under different labels.
std::string unvariable(const std::string& key, const std::vector<std::string>& engines) {
  if (key == "name") return "the scenario's name labels the sweep, not the physics";
  if (key == "frame_interval") return "the search sets the frame interval itself";
  if (key.rfind("engine.", 0) != 0) return "";
  const size_t dot = key.find('.', 7);
  const std::string engine = key.substr(7, dot == std::string::npos ? dot : dot - 7);
  const std::string field = dot == std::string::npos ? "" : key.substr(dot + 1);
  if (field == "dt") return "the search sets each engine's dt itself";
  if (field == "integrator") return "-i chooses the integrators the search tries";
  if (!engines.empty() && std::find(engines.begin(), engines.end(), engine) == engines.end())
    return "the engine " + engine + " is left out by -e";
  return "";
}

/// Throws UserError naming the option when the --vary keys cannot make an honest map: a key
/// varied twice, a key also given to --set, or a key the search sets itself.
void refuse_vary_conflicts(const MapArgs& a) {
  for (size_t i = 0; i < a.options.varied.size(); ++i) {
    const std::string& key = a.options.varied[i].key;
    const std::string option = "--vary " + a.vary[i];
    for (size_t j = 0; j < i; ++j)
      if (a.options.varied[j].key == key)
        throw UserError(option + ": " + key + " is varied twice (--vary " + a.vary[j] +
                        "); give each key once, with all its values");
    for (const std::string& o : a.overrides)
      if (override_key(o) == key)
        throw UserError(option + ": " + key + " is also set by --set " + o +
                        "; vary it or set it, not both");
    if (const std::string why = unvariable(key, a.options.search.engines); !why.empty())
      throw UserError(option + ": " + key + " cannot be varied: " + why);
  }
}

/// Throws UserError naming the --vary option (not --set, which it is applied as) when one of
/// its values is not a valid value of its key; checked before any work.
template <class Load>
void check_vary_values(const MapArgs& a, const Load& load) {
  load({});  // the scenario itself first: its own errors are its own
  for (size_t i = 0; i < a.options.varied.size(); ++i) {
    const VariedKey& k = a.options.varied[i];
    for (size_t v = 0; v < k.values.size(); ++v) {
      try {
        load({k.override_text(v)});
      } catch (const UserError& e) {
        throw UserError(
            as_option_error(e.what(), k.key, "--vary " + a.vary[i] + ": the value " + k.values[v]));
      }
    }
  }
}

int execute_map(MapArgs a) {
  MapOptions& o = a.options;
  o.search.progress = !a.quiet;
  for (const std::string& v : a.vary) o.varied.push_back(parse_varied_key(v));
  refuse_vary_conflicts(a);
  const auto load = [&a](const std::vector<std::string>& point) {
    std::vector<std::string> overrides = a.overrides;
    overrides.insert(overrides.end(), point.begin(), point.end());
    Scenario sc = load_or_seed(a.scenario_path, overrides, a.options.search.engines);
    sc.max_run_seconds = a.max_run_seconds;
    return sc;
  };
  check_vary_values(a, load);
  if (o.out_dir.empty()) o.out_dir = "out/" + load({}).name + "-map";
  refuse_overwriting_input(a.scenario_path, o.out_dir, "map_scenario.toml");
  const OutputLock lock(o.out_dir);
  const std::vector<MapRow> rows = run_map(load, o);
  std::cout << map_summary(o.varied, rows, o.search.method) << std::flush;
  if (o.search.progress) std::cerr << "wrote " << o.out_dir << "/map.csv\n";
  return kExitOk;
}

}  // namespace

Command add_map_command(CLI::App& app) {
  auto a = std::make_shared<MapArgs>();
  StabilityOptions& s = a->options.search;
  CLI::App* map = app.add_subcommand(
      "map",
      "Map the largest stable time step over a family of scenes: the stability search of\n"
      "`clothbench stability` at every point of a grid of one or two varied scenario keys.\n"
      "Writes map.csv (the varied values, then the columns of stability.csv), one stability\n"
      "sweep per point under points/, and map_scenario.toml, which --resume checks.\n"
      "Examples:\n"
      "  clothbench map -e custom-rk4 -i symplectic-euler --vary cloth.particles=9,17,33,65 \\\n"
      "      --set cloth.total_mass=625\n"
      "  clothbench map SCEN --vary cloth.stiffness.structural=1e2:1e5:log:7 --vary "
      "cloth.damping=0,10");
  map->add_option("scenario", a->scenario_path,
                  "scenario file (TOML); default: the embedded seed scene");
  map->add_option("--vary", a->vary,
                  "KEY=V1,V2,... or KEY=A:B:log:N or KEY=A:B:lin:N: a scenario key (as --set\n"
                  "names it) and its values; once or twice (a two-key grid). cloth.particles=N\n"
                  "means a square N x N grid (set cloth.total_mass to keep the mass)")
      ->required()
      ->allow_extra_args(false);
  map->add_option("--out,-o", a->options.out_dir,
                  "output folder (default: out/<scenario name>-map)");
  map->add_option("--engine,-e", s.engines, "search only this engine (repeatable)")
      ->allow_extra_args(false);
  add_integrator_option(map, s.integrators, "search");
  map->add_option("--dt-max", s.dt_max, "largest dt tried (s)")
      ->capture_default_str()
      ->check(positive_number());
  map->add_option("--rel-tol", s.rel_tol, "bisection tolerance, as for stability")
      ->capture_default_str()
      ->check(positive_number());
  map->add_option("--jobs,-j", s.jobs, "searches run at once (default: all cores)")
      ->check(positive_integer());
  map->add_flag("--resume", s.resume,
                "keep the points and rows already searched and search only the rest (refused\n"
                "for another scenario, other --vary values or other options)");
  map->add_option("--set,-s", a->overrides, "override a scenario key at every point (repeatable)")
      ->allow_extra_args(false);
  add_growth_options(map, s);
  add_shard_option(map, a->options.shard);
  add_max_run_seconds(map, a->max_run_seconds);
  add_allow_external(map);
  map->add_flag("--quiet,-q", a->quiet, "no progress on stderr");
  return {map, [a] { return execute_map(*a); }, true};
}

}  // namespace clothbench::cli
