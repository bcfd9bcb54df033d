#include "harness/regression_check.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "harness/csv_writer.hpp"
#include "harness/runner.hpp"
#include "harness/scenario_loader.hpp"
#include "harness/stability_sweep.hpp"
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
  for (const auto& [key, node] : root) {
    const std::string name(key.str());
    if (name == "stability") continue;
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
    if (const toml::array* a = (*s)["integrators"].as_array())
      for (const auto& v : *a) t.stability_integrators.push_back(v.value_or(std::string()));
  }
  return t;
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

const char* kToleranceTemplate =
    R"(# How far each gated quantity may move before `clothbench check` fails, as
# allowed = abs + rel * |baseline|. Edit the figures with a reason: the engine is
# deterministic, so an unchanged build reproduces its baseline to the last bit; the
# widths below only absorb round-off differences between compilers and CPUs.

# RMS distance (m) between the final shape and the recorded one, per engine: a
# micrometre on metre-sized cloth is far below any visible change
final_shape_rms = { abs = 1e-6 }
# exact facts of the run
stable = { abs = 0 }
steps = { abs = 0 }
force_evals = { abs = 0 }
# CG stops on a residual test: round-off can move a solve by an iteration now and then
cg_iterations = { rel = 0.01 }
# energies and distances (J, m): one part in a thousand, plus a floor for values near zero
max_energy_error = { rel = 1e-3, abs = 1e-9 }
final_rms_vs_reference = { rel = 1e-3, abs = 1e-9 }
max_rms_vs_reference = { rel = 1e-3, abs = 1e-9 }
final_com_y = { abs = 1e-6 }
drape_coefficient = { abs = 1e-4 }
)";

}  // namespace

std::vector<Gate> check_scenario(const std::string& scenario_path, const CheckOptions& o) {
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

  RunOptions ro;
  ro.progress = o.progress;
  const RunResult result = run_scenario(sc, ro);
  std::vector<StabilityRow> stability;
  if (tol.stability) {
    StabilityOptions so;
    so.out_dir = (fs::temp_directory_path() / ("clothbench-check-" + sc.name)).string();
    so.engines = {tol.stability_engine};
    so.integrators = tol.stability_integrators;
    so.rel_tol = tol.stability_rel_tol;
    so.jobs = o.jobs;
    so.progress = o.progress;
    stability = run_stability(sc, so);
    fs::remove_all(so.out_dir);
  }

  std::vector<Gate> gates;
  auto gate = [&](const std::string& engine, const std::string& quantity, double base, double now,
                  double allowed, double difference) {
    Gate g{sc.name, engine, quantity, base, now, difference, allowed, true, ""};
    const bool both_nan = std::isnan(base) && std::isnan(now);
    g.pass = both_nan || difference <= allowed;
    if (!g.pass) g.note = std::isnan(difference) ? "one side is missing" : "moved";
    gates.push_back(g);
  };

  if (o.update) {
    make_directories(dir.string());
    // the previous baseline, if any, to say what changed
    std::map<std::string, double> old;
    if (fs::exists(dir / "metrics.csv"))
      for (const auto& r : read_csv(dir / "metrics.csv", {"engine", "quantity", "value"}))
        old[r[0] + "/" + r[1]] = to_number(r[2], dir / "metrics.csv");
    CsvWriter metrics((dir / "metrics.csv").string(), {"engine", "quantity", "value"});
    for (size_t i = 0; i < result.runs.size(); ++i)
      for (const auto& [q, v] : run_metrics(result, i)) {
        metrics.add(result.runs[i].spec.name).add(q).add(v).end_row();
        const std::string k = result.runs[i].spec.name + "/" + q;
        const double before = old.count(k) ? old[k] : NAN;
        if (!(before == v) && !(std::isnan(before) && std::isnan(v))) {
          Gate g{sc.name, result.runs[i].spec.name,        q, before, v, std::abs(v - before), 0,
                 true,    old.count(k) ? "updated" : "new"};
          gates.push_back(g);
        }
      }
    CsvWriter shape((dir / "shape.csv").string(), {"engine", "i", "j", "x", "y", "z"});
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
    if (tol.stability) {
      CsvWriter st((dir / "stability.csv").string(),
                   {"engine", "integrator", "stable_dt", "first_unstable_dt"});
      for (const StabilityRow& r : stability)
        st.add(r.engine).add(r.integrator).add(r.stable_dt).add(r.first_unstable_dt).end_row();
      st.commit();
    }
    return gates;
  }

  // metrics
  const fs::path mpath = dir / "metrics.csv";
  std::map<std::string, double> base;
  for (const auto& r : read_csv(mpath, {"engine", "quantity", "value"}))
    base[r[0] + "/" + r[1]] = to_number(r[2], mpath);
  for (size_t i = 0; i < result.runs.size(); ++i) {
    const std::string& engine = result.runs[i].spec.name;
    const auto now = run_metrics(result, i);
    for (const std::string& q : kMetricQuantities) {
      const auto it = base.find(engine + "/" + q);
      if (it == base.end()) {
        gates.push_back({sc.name, engine, q, NAN, now.at(q), NAN, 0, false, "not in the baseline"});
        continue;
      }
      const double b = it->second, v = now.at(q);
      gate(engine, q, b, v, tol.quantity.at(q).allowed(b), std::abs(v - b));
    }
  }
  // final shapes
  const fs::path spath = dir / "shape.csv";
  std::map<std::string, cloth::Matrix3X> shapes;
  const Eigen::Index np = result.model.particle_count();
  for (const auto& r : read_csv(spath, {"engine", "i", "j", "x", "y", "z"})) {
    auto& m = shapes[r[0]];
    if (m.cols() == 0) m = cloth::Matrix3X::Constant(3, np, NAN);
    const long p =
        std::lround(to_number(r[2], spath)) * result.model.nu + std::lround(to_number(r[1], spath));
    if (p < 0 || p >= np) throw std::runtime_error(spath.string() + ": particle outside the grid");
    for (int a = 0; a < 3; ++a) m(a, p) = to_number(r[static_cast<size_t>(3 + a)], spath);
  }
  for (const EngineRun& run : result.runs) {
    const auto it = shapes.find(run.spec.name);
    if (it == shapes.end()) {
      gates.push_back({sc.name, run.spec.name, "final_shape_rms", NAN, NAN, NAN, 0, false,
                       "not in the baseline"});
      continue;
    }
    const double rms =
        std::sqrt((run.snapshots.back() - it->second).colwise().squaredNorm().mean());
    gate(run.spec.name, "final_shape_rms", 0.0, rms,
         tol.quantity.at("final_shape_rms").allowed(0.0), rms);
  }
  // stability limits: the same search must land in the same bisection interval
  if (tol.stability) {
    const fs::path stpath = dir / "stability.csv";
    std::map<std::string, std::pair<double, double>> limits;
    for (const auto& r :
         read_csv(stpath, {"engine", "integrator", "stable_dt", "first_unstable_dt"}))
      limits[r[0] + "/" + r[1]] = {to_number(r[2], stpath), to_number(r[3], stpath)};
    for (const StabilityRow& r : stability) {
      const std::string name = r.engine + "/" + r.integrator;
      const auto it = limits.find(name);
      if (it == limits.end()) {
        gates.push_back(
            {sc.name, name, "stable_dt", NAN, r.stable_dt, NAN, 0, false, "not in the baseline"});
        continue;
      }
      const double b = it->second.first;
      gate(name, "stable_dt", b, r.stable_dt, tol.stability_rel_tol * b, std::abs(r.stable_dt - b));
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
    std::snprintf(line, sizeof line, "%-18s %-32s %-22s %14s %14s %11s %11s  %s\n",
                  g.scenario.c_str(), g.engine.c_str(), g.quantity.c_str(), num(g.baseline).c_str(),
                  num(g.now).c_str(), num(g.difference).c_str(), num(g.allowed).c_str(),
                  (g.note.empty() ? std::string(g.pass ? "ok" : "FAIL")
                                  : std::string(g.pass ? "" : "FAIL: ") + g.note)
                      .c_str());
    o << line;
  }
  return o.str();
}

}  // namespace clothbench
