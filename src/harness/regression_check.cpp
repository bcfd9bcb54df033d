#include "harness/regression_check.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "harness/csv_writer.hpp"
#include "harness/runner.hpp"
#include "harness/scenario_loader.hpp"
#include "harness/stability_sweep.hpp"
#include "harness/csv_reader.hpp"
#include "harness/sweep.hpp"

namespace clothbench {

namespace fs = std::filesystem;

namespace {

// allowed difference: abs + rel * |baseline|
struct Tolerance {
  double abs = 0;
  double rel = 0;
  double allowed(double baseline) const { return abs + rel * std::abs(baseline); }
};

struct Tolerances {
  std::map<std::string, Tolerance> quantity;  // by quantity name
  bool stability = false;
  std::string stability_engine;
  std::vector<std::string> stability_integrators;
  double stability_rel_tol = 0.02;
  bool stability_adjacent = false;  // brackets that only share an end pass too
  // [ungated.<engine>]: quantities not gated for that engine, with the reason
  std::map<std::string, std::map<std::string, std::string>> ungated;
  // [mirror]: engines whose final shape is compared up to the scene's mirror image
  std::set<std::string> mirrored;
};

// the quantities of metrics.csv, in the order they are gated
const std::vector<std::string> kMetricQuantities = {"stable",
                                                    "steps",
                                                    "force_evals",
                                                    "cg_iterations",
                                                    "max_energy_error",
                                                    "final_rms_vs_reference",
                                                    "max_rms_vs_reference",
                                                    "drape_coefficient",
                                                    "final_com_y"};

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw std::runtime_error("cannot read " + p.string());
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::vector<std::string>> read_csv(const fs::path& p,
                                               const std::vector<std::string>& header) {
  std::istringstream in(read_file(p));
  std::string line;
  std::getline(in, line);
  if (split_csv_line(line) != header)
    throw std::runtime_error(p.string() + ": expected the header " + [&] {
      std::string h;
      for (const auto& x : header) h += (h.empty() ? "" : ",") + x;
      return h;
    }());
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    rows.push_back(split_csv_line(line));
    if (rows.back().size() != header.size())
      throw std::runtime_error(p.string() + ": a row with " + std::to_string(rows.back().size()) +
                               " fields for " + std::to_string(header.size()) + " columns");
  }
  return rows;
}

double to_number(const std::string& s, const fs::path& file) {
  if (s.empty()) return NAN;
  try {
    return std::stod(s);
  } catch (const std::exception&) {
    throw std::runtime_error(file.string() + ": \"" + s + "\" is not a number");
  }
}

Tolerances read_tolerances(const fs::path& p) {
  Tolerances t;
  toml::table root;
  try {
    root = toml::parse(read_file(p), p.string());
  } catch (const toml::parse_error& e) {
    throw std::runtime_error(p.string() + ":" + std::to_string(e.source().begin.line) + ": " +
                             std::string(e.description()));
  }
  const std::vector<std::string> known = [] {
    std::vector<std::string> k = kMetricQuantities;
    k.push_back("final_shape_rms");
    return k;
  }();
  auto strings = [&](toml::node_view<const toml::node> node, const std::string& where) {
    std::vector<std::string> out;
    const toml::array* a = node.as_array();
    if (!a) throw std::runtime_error(p.string() + ": " + where + ": expected an array of strings");
    for (const auto& v : *a) {
      if (!v.is_string())
        throw std::runtime_error(p.string() + ": " + where + ": expected an array of strings");
      out.push_back(v.value_or(std::string()));
    }
    return out;
  };
  for (const auto& [key, node] : root) {
    const std::string name(key.str());
    if (name == "stability" || name == "ungated" || name == "mirror") continue;
    if (std::find(known.begin(), known.end(), name) == known.end())
      throw std::runtime_error(p.string() + ": unknown quantity \"" + name + "\"");
    const toml::table* tab = node.as_table();
    if (!tab)
      throw std::runtime_error(p.string() + ": " + name + ": expected { abs = ..., rel = ... }");
    Tolerance tol;
    tol.abs = (*tab)["abs"].value_or(0.0);
    tol.rel = (*tab)["rel"].value_or(0.0);
    t.quantity[name] = tol;
  }
  for (const std::string& q : known)
    if (!t.quantity.count(q)) throw std::runtime_error(p.string() + ": no tolerance for " + q);
  if (const toml::table* s = root["stability"].as_table()) {
    t.stability = true;
    t.stability_engine = (*s)["engine"].value_or(std::string());
    t.stability_rel_tol = (*s)["rel_tol"].value_or(0.02);
    t.stability_adjacent = (*s)["adjacent"].value_or(false);
    if (const toml::array* a = (*s)["integrators"].as_array())
      for (const auto& v : *a) t.stability_integrators.push_back(v.value_or(std::string()));
  }
  if (const toml::table* u = root["ungated"].as_table()) {
    for (const auto& [engine_key, node] : *u) {
      const std::string engine(engine_key.str()), where = "ungated." + engine;
      const toml::table* e = node.as_table();
      if (!e)
        throw std::runtime_error(p.string() + ": " + where +
                                 ": expected { quantities = [...], reason = \"...\" }");
      const std::string reason = (*e)["reason"].value_or(std::string());
      if (reason.empty()) throw std::runtime_error(p.string() + ": " + where + ": no reason");
      for (const std::string& q : strings((*e)["quantities"], where + ".quantities")) {
        if (std::find(known.begin(), known.end(), q) == known.end())
          throw std::runtime_error(p.string() + ": " + where + ": unknown quantity \"" + q + "\"");
        t.ungated[engine][q] = reason;
      }
    }
  }
  if (const toml::table* m = root["mirror"].as_table())
    for (const std::string& e : strings((*m)["engines"], "mirror.engines")) t.mirrored.insert(e);
  return t;
}

// throws, naming the file, when tolerances name an engine the scenario does not have or ask
// for a mirror image of a grid one particle wide
void check_tolerance_engines(const Tolerances& t, const Scenario& sc, const fs::path& p) {
  auto has = [&](const std::string& name) {
    return std::any_of(sc.engines.begin(), sc.engines.end(),
                       [&](const EngineSpec& e) { return e.name == name; });
  };
  for (const auto& [engine, q] : t.ungated)
    if (!has(engine))
      throw std::runtime_error(p.string() + ": [ungated." + engine + "] names an engine " +
                               sc.name + " does not have");
  for (const std::string& engine : t.mirrored)
    if (!has(engine))
      throw std::runtime_error(p.string() + ": [mirror] names engine " + engine + ", which " +
                               sc.name + " does not have");
  if (!t.mirrored.empty() && sc.scene.cloth.nu < 2)
    throw std::runtime_error(p.string() + ": [mirror] needs a grid at least 2 particles wide");
}

// why a quantity is not gated for engines of a kind (empty: it is gated)
std::string ungated_reason(const std::string& kind, const std::string& quantity) {
  if (kind == "bullet-softbody" && quantity == "max_energy_error")
    return "not gated: 0 by construction (bullet-softbody books its energy balance as "
           "dissipated)";
  return "";
}

// the figures of one engine's run that metrics.csv records
std::map<std::string, double> run_metrics(const RunResult& r, size_t i) {
  const EngineRun& run = r.runs[i];
  const std::vector<Divergence>& d = r.divergence[i];
  double worst = 0;
  for (const Divergence& x : d) worst = std::max(worst, x.rms_distance);
  return {{"stable", run.stable ? 1.0 : 0.0},
          {"steps", double(run.counters.steps)},
          {"force_evals", double(run.counters.force_evals)},
          {"cg_iterations", double(run.counters.cg_iterations)},
          {"max_energy_error", run.max_energy_error},
          {"final_rms_vs_reference", d.empty() ? NAN : d.back().rms_distance},
          {"max_rms_vs_reference", d.empty() ? NAN : worst},
          {"drape_coefficient", final_drape_coefficient(r, run)},
          {"final_com_y", run.frames.back().com.y()}};
}

using Metrics = std::map<std::string, double>;  // by "engine/quantity"
using Shapes = std::map<std::string, cloth::Matrix3X>;

// a baseline's stability limits: the search's bracket [stable_dt, first_unstable_dt)
struct Bracket {
  double stable_dt = 0;          // s, found stable
  double first_unstable_dt = 0;  // s, found unstable (infinity: none up to dt_max)
};
using Brackets = std::map<std::string, Bracket>;  // by "engine/integrator"

const std::vector<std::string> kMetricsHeader = {"engine", "quantity", "value"};
const std::vector<std::string> kShapeHeader = {"engine", "i", "j", "x", "y", "z"};
const std::vector<std::string> kStabilityHeader = {"engine", "integrator", "stable_dt",
                                                   "first_unstable_dt"};

Metrics read_metrics(const fs::path& p) {
  Metrics m;
  for (const auto& r : read_csv(p, kMetricsHeader)) m[r[0] + "/" + r[1]] = to_number(r[2], p);
  return m;
}

// every engine's final shape, 3 by #P (NaN for particles the file leaves out)
Shapes read_shapes(const fs::path& p, const cloth::Model& model) {
  Shapes shapes;
  const Eigen::Index np = model.particle_count();
  for (const auto& r : read_csv(p, kShapeHeader)) {
    auto& m = shapes[r[0]];
    if (m.cols() == 0) m = cloth::Matrix3X::Constant(3, np, NAN);
    const long i = std::lround(to_number(r[1], p)), j = std::lround(to_number(r[2], p));
    if (i < 0 || i >= model.nu || j < 0 || j >= model.nv)
      throw std::runtime_error(p.string() + ": particle (" + r[1] + ", " + r[2] + ") outside the " +
                               std::to_string(model.nu) + " x " + std::to_string(model.nv) +
                               " grid");
    for (int a = 0; a < 3; ++a) m(a, j * model.nu + i) = to_number(r[size_t(3 + a)], p);
  }
  return shapes;
}

Brackets read_brackets(const fs::path& p) {
  Brackets b;
  for (const auto& r : read_csv(p, kStabilityHeader))
    b[r[0] + "/" + r[1]] = {to_number(r[2], p), to_number(r[3], p)};
  return b;
}

Brackets brackets_of(const std::vector<StabilityRow>& rows) {
  Brackets b;
  for (const StabilityRow& r : rows)
    b[r.engine + "/" + r.integrator] = {r.stable_dt, r.first_unstable_dt};
  return b;
}

// the scene's left-right mirror image of a 3 by #P shape: reflected across the plane through
// the cloth's rest centre normal to its grid's u axis, particle (i, j) taking the place of
// (nu - 1 - i, j)
cloth::Matrix3X mirror_image(const cloth::Matrix3X& x, const cloth::Model& m) {
  const cloth::Vector3 c = m.x0.rowwise().mean();
  const cloth::Vector3 u = (m.x0.col(1) - m.x0.col(0)).normalized();
  cloth::Matrix3X y(3, x.cols());
  for (int j = 0; j < m.nv; ++j)
    for (int i = 0; i < m.nu; ++i) {
      const cloth::Vector3 q = x.col(j * m.nu + (m.nu - 1 - i));
      y.col(j * m.nu + i) = q - 2.0 * (q - c).dot(u) * u;
    }
  return y;
}

// RMS over particles of the distance between two shapes (m)
double shape_rms(const cloth::Matrix3X& a, const cloth::Matrix3X& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

// the engine part of a "engine/quantity" key
std::string engine_of(const std::string& key) {
  return key.substr(0, key.rfind('/'));
}

void write_baseline(const fs::path& dir, const RunResult& result,
                    const std::vector<StabilityRow>* stability) {
  make_directories(dir.string());
  CsvWriter metrics((dir / "metrics.csv").string(), kMetricsHeader);
  for (size_t i = 0; i < result.runs.size(); ++i)
    for (const auto& [q, v] : run_metrics(result, i))
      metrics.add(result.runs[i].spec.name).add(q).add(v).end_row();
  CsvWriter shape((dir / "shape.csv").string(), kShapeHeader);
  for (const EngineRun& run : result.runs) {
    const cloth::Matrix3X& x = run.snapshots.back();
    for (Eigen::Index p = 0; p < x.cols(); ++p)
      shape.add(run.spec.name)
          .add(int(p % result.model.nu))
          .add(int(p / result.model.nu))
          .add(x(0, p))
          .add(x(1, p))
          .add(x(2, p))
          .end_row();
  }
  metrics.commit();
  shape.commit();
  if (stability) {
    CsvWriter st((dir / "stability.csv").string(), kStabilityHeader);
    for (const StabilityRow& r : *stability)
      st.add(r.engine).add(r.integrator).add(r.stable_dt).add(r.first_unstable_dt).end_row();
    st.commit();
  } else {
    // limits no longer searched must not linger as a baseline nobody checks
    fs::remove(dir / "stability.csv");
  }
}

// what --update changed: metrics, final shapes (RMS per engine) and stability limits
std::vector<Gate> changes(const std::string& scenario, const Metrics& old_metrics,
                          const Shapes& old_shapes, const Brackets& old_brackets,
                          const RunResult& result, const Brackets& now_brackets) {
  std::vector<Gate> gates;
  auto change = [&](const std::string& engine, const std::string& quantity, double before,
                    double after, const std::string& note) {
    const double d = std::isinf(before) && before == after ? 0.0 : std::abs(after - before);
    gates.push_back({scenario, engine, quantity, before, after, d, NAN, true, note, "-"});
  };
  auto same = [](double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); };
  // metrics, and engines that are no longer run
  std::set<std::string> now_engines;
  for (size_t i = 0; i < result.runs.size(); ++i) {
    const std::string& engine = result.runs[i].spec.name;
    now_engines.insert(engine);
    for (const auto& [q, v] : run_metrics(result, i)) {
      const auto it = old_metrics.find(engine + "/" + q);
      if (it == old_metrics.end())
        change(engine, q, NAN, v, "new");
      else if (!same(it->second, v))
        change(engine, q, it->second, v, "updated");
    }
  }
  std::set<std::string> removed;
  for (const auto& [key, v] : old_metrics)
    if (!now_engines.count(engine_of(key))) removed.insert(engine_of(key));
  for (const auto& [engine, x] : old_shapes)
    if (!now_engines.count(engine)) removed.insert(engine);
  for (const std::string& engine : removed) change(engine, "ran", 1, 0, "removed");
  // how far each final shape moved
  for (const EngineRun& run : result.runs) {
    const auto it = old_shapes.find(run.spec.name);
    if (it == old_shapes.end()) continue;
    const double rms = shape_rms(run.snapshots.back(), it->second);
    if (!(rms == 0.0)) change(run.spec.name, "final_shape_rms", 0.0, rms, "moved");
  }
  // stability limits
  for (const auto& [key, b] : now_brackets) {
    const auto it = old_brackets.find(key);
    if (it == old_brackets.end()) {
      change(key, "stable_dt", NAN, b.stable_dt, "new");
      change(key, "first_unstable_dt", NAN, b.first_unstable_dt, "new");
      continue;
    }
    if (!same(it->second.stable_dt, b.stable_dt))
      change(key, "stable_dt", it->second.stable_dt, b.stable_dt, "updated");
    if (!same(it->second.first_unstable_dt, b.first_unstable_dt))
      change(key, "first_unstable_dt", it->second.first_unstable_dt, b.first_unstable_dt,
             "updated");
  }
  for (const auto& [key, b] : old_brackets)
    if (!now_brackets.count(key)) change(key, "stable_dt", b.stable_dt, NAN, "removed");
  return gates;
}

const char* kToleranceTemplate =
    R"(# How far each gated quantity may move before `clothbench check` fails, as
# allowed = abs + rel * |baseline|. GENERATED DEFAULTS: replace every reason below with what
# you measured on this scenario (the spread between builds with different -march flags, or
# between runs), and make each width no wider than that. An unchanged build reproduces its
# baseline to the last bit: the widths only absorb round-off differences between compilers
# and CPUs.

# RMS distance (m) between the final shape and the recorded one, per engine
final_shape_rms = { abs = 1e-6 }
# exact facts of the run
stable = { abs = 0 }
steps = { abs = 0 }
force_evals = { abs = 0 }
cg_iterations = { abs = 0 }
# energies and distances (J, m), plus a floor for values near zero
max_energy_error = { rel = 1e-3, abs = 1e-9 }
final_rms_vs_reference = { rel = 1e-3, abs = 1e-9 }
max_rms_vs_reference = { rel = 1e-3, abs = 1e-9 }
final_com_y = { abs = 1e-6 }
drape_coefficient = { abs = 1e-4 }
)";

}  // namespace

ScratchFolder::ScratchFolder(const std::string& prefix) {
  const std::string pattern = (fs::temp_directory_path() / (prefix + "XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  if (!::mkdtemp(name.data()))
    throw std::runtime_error("cannot create a temporary folder " + pattern + ": " +
                             std::strerror(errno));
  m_path = name.data();
}

ScratchFolder::~ScratchFolder() {
  std::error_code ignored;  // nothing sensible to do about a folder that will not go
  fs::remove_all(m_path, ignored);
}

std::vector<Gate> check_scenario(const std::string& scenario_path, const CheckOptions& o) {
  if (o.update && !o.overrides.empty() && !o.record_perturbed)
    throw std::invalid_argument(
        "--update with --set would record a perturbed engine as the baseline, which then hides "
        "the very change it should catch; drop the --set overrides, or add --record-perturbed "
        "if a perturbed baseline is what you mean");
  const Scenario sc = load_scenario(scenario_path, o.overrides);
  const fs::path dir = fs::path(o.baseline_dir) / sc.name;
  const fs::path tol_path = dir / "tolerances.toml";
  if (o.update && !fs::exists(tol_path)) {
    make_directories(dir.string());
    AtomicFile f(tol_path.string());
    f.write(kToleranceTemplate);
    f.commit();
  }
  if (!fs::exists(tol_path))
    throw std::runtime_error("no baseline for scenario " + sc.name + ": " + tol_path.string() +
                             " is missing (record one with clothbench check --update)");
  const Tolerances tol = read_tolerances(tol_path);
  check_tolerance_engines(tol, sc, tol_path);

  RunOptions ro;
  ro.progress = o.progress;
  const RunResult result = run_scenario(sc, ro);
  std::vector<StabilityRow> stability;
  if (tol.stability) {
    // the search writes its table to a folder of its own, gone on every way out of this block
    const ScratchFolder scratch("clothbench-check-" + sc.name + "-");
    StabilityOptions so;
    so.out_dir = scratch.path();
    so.engines = {tol.stability_engine};
    so.integrators = tol.stability_integrators;
    so.rel_tol = tol.stability_rel_tol;
    so.jobs = o.jobs;
    so.progress = o.progress;
    stability = run_stability(sc, so);
  }
  const Brackets now_brackets = brackets_of(stability);

  const fs::path mpath = dir / "metrics.csv", spath = dir / "shape.csv",
                 stpath = dir / "stability.csv";
  if (o.update) {
    // the previous baseline, if any, to say what changed
    const Metrics old_metrics = fs::exists(mpath) ? read_metrics(mpath) : Metrics();
    Shapes old_shapes;
    std::string grid_changed;
    try {
      if (fs::exists(spath)) old_shapes = read_shapes(spath, result.model);
    } catch (const std::runtime_error& e) {
      grid_changed = e.what();  // a grid of another size: no shape to compare with
    }
    const Brackets old_brackets = fs::exists(stpath) ? read_brackets(stpath) : Brackets();
    write_baseline(dir, result, tol.stability ? &stability : nullptr);
    std::vector<Gate> gates =
        changes(sc.name, old_metrics, old_shapes, old_brackets, result, now_brackets);
    if (!grid_changed.empty())
      gates.push_back({sc.name, "", "final_shape_rms", NAN, NAN, NAN, NAN, true,
                       "previous shapes not comparable: " + grid_changed, "-"});
    return gates;
  }

  std::vector<Gate> gates;
  auto gate = [&](const std::string& engine, const std::string& quantity, double base, double now,
                  double allowed, double difference) {
    Gate g{sc.name, engine, quantity, base, now, difference, allowed, true, "", ""};
    const bool both_nan = std::isnan(base) && std::isnan(now);
    g.pass = both_nan || difference <= allowed;
    if (!g.pass) g.note = std::isnan(difference) ? "one side is missing" : "moved";
    gates.push_back(g);
  };
  auto fail = [&](const std::string& engine, const std::string& quantity, double base, double now,
                  const std::string& why) {
    gates.push_back({sc.name, engine, quantity, base, now, NAN, 0, false, why, ""});
  };

  // engines: every one recorded must have run, every one that ran must have a baseline
  const Metrics base = read_metrics(mpath);
  const Shapes shapes = read_shapes(spath, result.model);
  std::set<std::string> recorded, ran;
  for (const auto& [key, v] : base) recorded.insert(engine_of(key));
  for (const auto& [engine, x] : shapes) recorded.insert(engine);
  for (const EngineRun& run : result.runs) ran.insert(run.spec.name);
  for (const std::string& engine : recorded)
    if (!ran.count(engine)) fail(engine, "ran", 1, 0, "recorded in the baseline but did not run");
  for (const std::string& engine : ran)
    if (!recorded.count(engine))
      fail(engine, "ran", 0, 1, "ran but has no baseline (record one with --update)");

  // metrics
  for (size_t i = 0; i < result.runs.size(); ++i) {
    const EngineSpec& spec = result.runs[i].spec;
    if (!recorded.count(spec.name)) continue;
    const auto now = run_metrics(result, i);
    for (const std::string& q : kMetricQuantities) {
      const auto it = base.find(spec.name + "/" + q);
      if (it == base.end()) {
        fail(spec.name, q, NAN, now.at(q), "not in the baseline");
        continue;
      }
      const double b = it->second, v = now.at(q);
      const auto listed = tol.ungated.find(spec.name);
      const std::string why = listed != tol.ungated.end() && listed->second.count(q)
                                  ? "not gated: " + listed->second.at(q)
                                  : ungated_reason(spec.kind, q);
      if (!why.empty()) {
        gates.push_back({sc.name, spec.name, q, b, v, std::abs(v - b), NAN, true, why, "-", false});
        continue;
      }
      gate(spec.name, q, b, v, tol.quantity.at(q).allowed(b), std::abs(v - b));
    }
  }
  // final shapes
  for (const EngineRun& run : result.runs) {
    if (!recorded.count(run.spec.name)) continue;
    const auto it = shapes.find(run.spec.name);
    if (it == shapes.end()) {
      fail(run.spec.name, "final_shape_rms", NAN, NAN, "no shape in the baseline");
      continue;
    }
    const auto listed = tol.ungated.find(run.spec.name);
    if (listed != tol.ungated.end() && listed->second.count("final_shape_rms")) {
      const double rms = shape_rms(run.snapshots.back(), it->second);
      gates.push_back({sc.name, run.spec.name, "final_shape_rms", 0.0, rms, rms, NAN, true,
                       "not gated: " + listed->second.at("final_shape_rms"), "-", false});
      continue;
    }
    double rms = shape_rms(run.snapshots.back(), it->second);
    bool mirrored = false;
    if (tol.mirrored.count(run.spec.name)) {
      // the engine may pick either side of the scene's symmetry: the nearer image counts
      const double m = shape_rms(run.snapshots.back(), mirror_image(it->second, result.model));
      mirrored = m < rms;
      rms = std::min(rms, m);
    }
    gate(run.spec.name, "final_shape_rms", 0.0, rms,
         tol.quantity.at("final_shape_rms").allowed(0.0), rms);
    if (mirrored && gates.back().pass) gates.back().note = "to the mirror image";
  }
  // stability limits: the recorded search found the limit in [stable_dt, first_unstable_dt);
  // the same search now must bracket a limit that can be the same one, so the two half-open
  // brackets must overlap (an adjacent bracket means the run at the shared dt changed verdict)
  const Brackets recorded_brackets = fs::exists(stpath) ? read_brackets(stpath) : Brackets();
  if (!tol.stability) {
    for (const auto& [key, b] : recorded_brackets)
      fail(key, "stable_dt", b.stable_dt, NAN,
           "recorded, but tolerances.toml has no [stability] table to search it");
  } else {
    if (!fs::exists(stpath)) read_file(stpath);  // throws, naming the missing file
    for (const auto& [key, b] : recorded_brackets)
      if (!now_brackets.count(key))
        fail(key, "stable_dt", b.stable_dt, NAN, "recorded in the baseline but not searched");
    for (const auto& [key, n] : now_brackets) {
      const auto it = recorded_brackets.find(key);
      if (it == recorded_brackets.end()) {
        fail(key, "stable_dt", NAN, n.stable_dt, "searched but has no baseline");
        continue;
      }
      const Bracket& b = it->second;
      const std::string miss = "now [" + format_double(n.stable_dt) + ", " +
                               format_double(n.first_unstable_dt) + ") misses [" +
                               format_double(b.stable_dt) + ", " +
                               format_double(b.first_unstable_dt) + ")";
      // both ends fail together: the two brackets cannot hold the same limit (with adjacent,
      // brackets that share an end may: the run at that dt turned the other way)
      const bool overlap =
          tol.stability_adjacent
              ? n.stable_dt <= b.first_unstable_dt && b.stable_dt <= n.first_unstable_dt
              : n.stable_dt < b.first_unstable_dt && b.stable_dt < n.first_unstable_dt;
      gates.push_back({sc.name, key, "stable_dt", b.stable_dt, n.stable_dt,
                       std::abs(n.stable_dt - b.stable_dt), NAN, overlap, overlap ? "" : miss,
                       "< " + format_double(b.first_unstable_dt)});
      const double d = std::isinf(b.first_unstable_dt) && b.first_unstable_dt == n.first_unstable_dt
                           ? 0.0
                           : std::abs(n.first_unstable_dt - b.first_unstable_dt);
      gates.push_back({sc.name, key, "first_unstable_dt", b.first_unstable_dt, n.first_unstable_dt,
                       d, NAN, overlap, overlap ? "" : miss, "> " + format_double(b.stable_dt)});
    }
  }
  return gates;
}

std::string format_gates(const std::vector<Gate>& gates) {
  std::ostringstream o;
  char line[512];
  std::snprintf(line, sizeof line, "%-18s %-32s %-22s %14s %14s %11s %11s  %s\n", "scenario",
                "engine", "quantity", "baseline", "now", "difference", "allowed", "verdict");
  o << line;
  for (const Gate& g : gates) {
    auto num = [](double v) {
      char b[32];
      std::snprintf(b, sizeof b, "%.6g", v);
      return std::string(b);
    };
    const std::string allowed = g.allowed_text.empty() ? num(g.allowed) : g.allowed_text;
    std::snprintf(line, sizeof line, "%-18s %-32s %-22s %14s %14s %11s %11s  %s\n",
                  g.scenario.c_str(), g.engine.c_str(), g.quantity.c_str(), num(g.baseline).c_str(),
                  num(g.now).c_str(), num(g.difference).c_str(), allowed.c_str(),
                  (g.note.empty() ? std::string(g.pass ? "ok" : "FAIL")
                                  : std::string(g.pass ? "" : "FAIL: ") + g.note)
                      .c_str());
    o << line;
  }
  return o.str();
}

}  // namespace clothbench
