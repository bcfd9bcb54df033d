#include "harness/accuracy_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "cloth/integrator.hpp"
#include "cloth/model.hpp"
#include "harness/csv_writer.hpp"
#include "harness/engine_factory.hpp"
#include "harness/progress.hpp"
#include "harness/runner.hpp"
#include "harness/scenario_loader.hpp"
#include "harness/scenario_writer.hpp"

namespace clothbench {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const std::vector<std::string> kWorkPrecisionHeader = {
    "engine", "integrator",       "dt",          "stable",        "error_final", "error_max",
    "wall_s", "wall_s_per_sim_s", "force_evals", "cg_iterations", "rerun"};
const std::vector<std::string> kResolutionHeader = {
    "engine",           "integrator",  "particles",     "dt",   "stable", "error_final",
    "wall_s_per_sim_s", "force_evals", "cg_iterations", "rerun"};
const std::vector<std::string> kReferenceHeader = {"study",     "engine",      "integrator", "dt",
                                                   "particles", "error_floor", "rerun"};

/// One configuration to run: an engine of a scenario with its integrator and dt set.
struct Config {
  EngineSpec spec;
  std::string integrator;  // "" for Bullet engines
  int grid = -1;           // resolution study: index into the grids; -1: time-step study
  std::string key;         // row key in its table
  std::string rerun;       // --set overrides that rerun it
};

/// A run of one configuration, its wall time the median over repeats.
struct TimedRun {
  EngineRun run;
  double wall_s = 0;  // s
};

std::string join_key(const std::string& a, const std::string& b, const std::string& c) {
  return a + "," + b + "," + c;
}

std::string grid_name(int nu, int nv) {
  return std::to_string(nu) + " x " + std::to_string(nv);
}

double rms_distance(const cloth::Matrix3X& a, const cloth::Matrix3X& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Throws unless dt divides the scenario's frame_interval (frames must land on steps).
void check_divides(const Scenario& sc, double dt, const std::string& what) {
  const double r = sc.frame_interval / dt;
  const double n = std::round(r);
  if (!(dt > 0) || !std::isfinite(r) || n < 1 || std::abs(r - n) > 1e-9 * r)
    throw std::invalid_argument(
        what + ": dt = " + format_double(dt) +
        " s does not divide frame_interval = " + format_double(sc.frame_interval) + " s of " +
        sc.source + " (every swept dt must: give --dts that divide it)");
}

/// The engines the options name, in scenario order; throws for a name the scenario lacks.
std::vector<EngineSpec> selected_engines(const Scenario& sc, const AccuracyOptions& o) {
  for (const std::string& name : o.engines) {
    if (std::none_of(sc.engines.begin(), sc.engines.end(),
                     [&](const EngineSpec& e) { return e.name == name; })) {
      std::string known;
      for (const EngineSpec& e : sc.engines) known += (known.empty() ? "" : ", ") + e.name;
      throw std::invalid_argument("--engine " + name + ": no such engine in " + sc.source +
                                  " (engines: " + known + ")");
    }
  }
  std::vector<EngineSpec> out;
  for (const EngineSpec& e : sc.engines)
    if (o.engines.empty() || std::count(o.engines.begin(), o.engines.end(), e.name) > 0)
      out.push_back(e);
  return out;
}

/// The integrators the options name, in cloth::all_integrators() order.
std::vector<std::string> selected_integrators(const AccuracyOptions& o) {
  std::string known;
  for (cloth::Integrator i : cloth::all_integrators())
    known += (known.empty() ? "" : ", ") + std::string(cloth::integrator_name(i));
  for (const std::string& name : o.integrators)
    if (!cloth::parse_integrator(name))
      throw std::invalid_argument("--integrator " + name +
                                  ": no such integrator (expected one of: " + known + ")");
  std::vector<std::string> out;
  for (cloth::Integrator i : cloth::all_integrators()) {
    const std::string name = cloth::integrator_name(i);
    if (o.integrators.empty() || std::count(o.integrators.begin(), o.integrators.end(), name) > 0)
      out.push_back(name);
  }
  return out;
}

/// The time steps swept for engine e, largest first.
std::vector<double> swept_dts(const Scenario& sc, const EngineSpec& e, const AccuracyOptions& o) {
  std::vector<double> dts = o.dts;
  if (dts.empty())
    for (int k = 0; k < o.halvings; ++k) dts.push_back(e.dt / std::ldexp(1.0, k));
  std::sort(dts.begin(), dts.end(), std::greater<double>());
  dts.erase(std::unique(dts.begin(), dts.end()), dts.end());
  for (double dt : dts) check_divides(sc, dt, "engine " + e.name);
  return dts;
}

/// The custom engine whose options the reference borrows: the scenario's reference engine when
/// it is custom, else its first custom engine; nullptr when it has none.
const EngineSpec* reference_base(const Scenario& sc) {
  if (sc.engines.empty()) return nullptr;
  const EngineSpec& r = sc.engines[static_cast<size_t>(sc.reference_index())];
  if (r.kind == EngineKind::custom) return &r;
  for (const EngineSpec& e : sc.engines)
    if (e.kind == EngineKind::custom) return &e;
  return nullptr;
}

/// Two configurations that differ in engine name only run the same computation: the resolved
/// TOML of the engine alone, its name blanked, says whether they do.
std::string signature(const EngineSpec& e, int grid) {
  Scenario s;
  s.engines = {e};
  s.engines[0].name = "";
  return std::to_string(grid) + "\n" + scenario_to_toml(s);
}

/// Runs spec once keeping what keep_positions asks, then repeats - 1 times more for the
/// median wall time (an unstable run is timed once: its cost is not a recommendation).
TimedRun timed_run(const Scenario& sc, const cloth::Model& model, const EngineSpec& spec,
                   int repeats, bool keep_positions) {
  TimedRun t{run_engine(sc, spec, model, nullptr, keep_positions), 0};
  std::vector<double> walls = {t.run.wall_s};
  if (t.run.stable)
    for (int r = 1; r < repeats; ++r)
      walls.push_back(run_engine(sc, spec, model, nullptr, false).wall_s);
  t.wall_s = median(walls);
  return t;
}

double simulated_s(const EngineRun& run) {
  return double(run.counters.steps) * run.spec.dt;
}

std::string optional_double(double v) {
  return std::isfinite(v) ? format_double(v) : "";
}

double parse_error(const std::string& s) {
  return s.empty() ? kInf : std::stod(s);
}

AccuracyRow parse_work_precision_row(const std::vector<std::string>& f, int particles) {
  AccuracyRow r;
  r.engine = f[0];
  r.integrator = f[1];
  r.particles = particles;
  r.dt = std::stod(f[2]);
  r.stable = f[3] == "1";
  r.error_final = parse_error(f[4]);
  r.error_max = parse_error(f[5]);
  r.wall_s = std::stod(f[6]);
  r.wall_s_per_sim_s = std::stod(f[7]);
  r.force_evals = std::stoll(f[8]);
  r.cg_iterations = std::stoll(f[9]);
  r.rerun = f[10];
  return r;
}

AccuracyRow parse_resolution_row(const std::vector<std::string>& f) {
  AccuracyRow r;
  r.engine = f[0];
  r.integrator = f[1];
  r.particles = std::stoi(f[2]);
  r.dt = std::stod(f[3]);
  r.stable = f[4] == "1";
  r.error_final = parse_error(f[5]);
  r.error_max = kNaN;
  r.wall_s_per_sim_s = std::stod(f[6]);
  r.force_evals = std::stoll(f[7]);
  r.cg_iterations = std::stoll(f[8]);
  r.rerun = f[9];
  if (r.rerun.size() >= 2 && r.rerun.front() == '"')
    r.rerun = r.rerun.substr(1, r.rerun.size() - 2);
  return r;
}

}  // namespace

double counted_work(const AccuracyRow& r) {
  if (r.integrator.empty()) return kNaN;
  return (double(r.force_evals) + kCgIterationCost * double(r.cg_iterations)) * double(r.particles);
}

namespace {

/// The key a row is ranked by within its engine (smaller is cheaper): the counted work of
/// the custom engine, and for a Bullet engine, whose work is not counted, steps times
/// particles (its cost per particle and step is fixed by its options: only dt and the grid
/// change between its rows).
double engine_cost(const AccuracyRow& r) {
  return r.integrator.empty() ? double(r.particles) / r.dt : counted_work(r);
}

/// a before b among rows of one engine: cheaper, then more accurate; equal rows keep their
/// order (the caller scans in row order and replaces only on strictly before)
bool before(const AccuracyRow& a, const AccuracyRow& b, double AccuracyRow::*error) {
  if (engine_cost(a) != engine_cost(b)) return engine_cost(a) < engine_cost(b);
  return a.*error < b.*error;
}

/// The cheapest stable row of rows[indices] (one engine's) whose error is within tolerance;
/// when none is, the most accurate stable row (found = false).
Recommendation recommend(const std::vector<AccuracyRow>& rows, const std::vector<size_t>& indices,
                         double tolerance, double AccuracyRow::*error, const std::string& engine) {
  Recommendation rec;
  rec.scope = "engine";
  rec.engine = engine;
  const AccuracyRow* best = nullptr;
  const AccuracyRow* closest = nullptr;
  for (size_t i : indices) {
    const AccuracyRow& r = rows[i];
    if (!r.stable || !std::isfinite(r.*error)) continue;
    if (!closest || r.*error < closest->*error) closest = &r;
    if (r.*error <= tolerance && (!best || before(r, *best, error))) best = &r;
  }
  rec.found = best != nullptr;
  if (best)
    rec.row = *best;
  else if (closest)
    rec.row = *closest;
  return rec;
}

/// Per engine (in order), then overall: the cheapest of the engines' choices, by counted
/// work when they are all the custom engine's, otherwise by wall time per simulated second
/// (the one cost Bullet and the custom engine share), then by error and engine order.
std::vector<Recommendation> recommend_all(const std::vector<AccuracyRow>& rows,
                                          const std::vector<std::string>& engines, double tolerance,
                                          double AccuracyRow::*error) {
  std::vector<Recommendation> out;
  for (const std::string& e : engines) {
    std::vector<size_t> mine;
    for (size_t i = 0; i < rows.size(); ++i)
      if (rows[i].engine == e) mine.push_back(i);
    out.push_back(recommend(rows, mine, tolerance, error, e));
  }
  Recommendation overall;
  overall.scope = "overall";
  const bool all_counted = std::all_of(out.begin(), out.end(), [](const Recommendation& r) {
    return !r.found || !r.row.integrator.empty();
  });
  const auto key = [&](const AccuracyRow& r) {
    return all_counted ? counted_work(r) : r.wall_s_per_sim_s;
  };
  const Recommendation* best = nullptr;
  for (const Recommendation& r : out) {
    if (!r.found) continue;
    if (!best || key(r.row) < key(best->row) ||
        (key(r.row) == key(best->row) && r.row.*error < best->row.*error))
      best = &r;
  }
  if (best) {
    overall.found = true;
    overall.engine = best->engine;
    overall.row = best->row;
  } else {
    // nothing meets the tolerance: the most accurate stable row of all, as per engine
    for (const Recommendation& r : out)
      if (!r.row.engine.empty() &&
          (overall.row.engine.empty() || r.row.*error < overall.row.*error))
        overall.row = r.row;
  }
  out.push_back(overall);
  return out;
}

/// The rows of an earlier reference.csv, by study (empty when there is none).
std::map<std::string, std::vector<std::string>> read_references(const std::string& path) {
  std::map<std::string, std::vector<std::string>> out;
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line)) return out;
  while (std::getline(in, line)) {
    std::vector<std::string> f = split_csv_line(line);
    if (f.size() >= 6) out[f[0]] = f;
  }
  return out;
}

/// Throws when an earlier sweep in the folder measured against another reference.
void check_resumable_reference(const std::string& path,
                               const std::map<std::string, std::vector<std::string>>& earlier,
                               const AccuracyReference& ref) {
  auto it = earlier.find(ref.study);
  if (it == earlier.end()) return;
  const std::vector<std::string>& f = it->second;
  const std::string particles = std::to_string(ref.nu * ref.nv);
  if (f[1] != ref.engine || f[3] != format_double(ref.dt) || f[4] != particles)
    throw std::runtime_error(path + ": cannot resume: the earlier sweep's " + ref.study +
                             " reference was " + f[1] + " rk4 at dt = " + f[3] + " s on " + f[4] +
                             " particles, this one is " + ref.engine +
                             " rk4 at dt = " + format_double(ref.dt) + " s on " + particles +
                             " particles (the swept time steps or resolutions changed); run "
                             "without --resume or choose another output folder");
}

void write_references(const std::string& path, const std::vector<AccuracyReference>& refs,
                      const std::vector<std::string>& reruns) {
  CsvWriter w(path, kReferenceHeader);
  for (size_t i = 0; i < refs.size(); ++i) {
    const AccuracyReference& r = refs[i];
    w.add(r.study).add(r.engine).add(std::string("rk4")).add(r.dt).add(r.nu * r.nv);
    w.add(optional_double(r.error_floor)).add(csv_field(reruns[i]));
    w.end_row();
  }
  w.commit();
}

/// The rows of table with these keys, in their order (read back after finish(): the file's
/// order is the rows() order).
std::vector<std::vector<std::string>> rows_in_order(const SweepTable& table,
                                                    const std::vector<std::string>& keys) {
  std::map<std::string, std::vector<std::string>> by_key;
  for (auto& f : table.rows()) by_key[table.key(f)] = f;
  std::vector<std::vector<std::string>> out;
  for (const std::string& k : keys) {
    auto it = by_key.find(k);
    if (it == by_key.end()) throw std::logic_error("accuracy: no row " + k + " after the sweep");
    out.push_back(it->second);
  }
  return out;
}

std::string rerun_at_grid(const EngineSpec& e, int r, double total_mass) {
  return "--set cloth.particles=[" + std::to_string(r) + "," + std::to_string(r) + "] " +
         "--set cloth.total_mass=" + format_double(total_mass) + " " + rerun_overrides(e);
}

}  // namespace

double fitted_order(const std::vector<double>& dts, const std::vector<double>& errors) {
  const size_t n = std::min(dts.size(), errors.size());
  if (n < 2) return kNaN;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < n; ++i) {
    const double lx = std::log(dts[i]), ly = std::log(errors[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  const double den = double(n) * sxx - sx * sx;
  return den > 0 ? (double(n) * sxy - sx * sy) / den : kNaN;
}

cloth::Vector3 bilinear_position(const cloth::Matrix3X& x, int nu, int nv, double u, double v) {
  // the cell holding (u, v), the last cell for u = 1 or v = 1
  const auto cell = [](int n, double w, int& k, double& f) {
    if (n < 2) {
      k = 0;
      f = 0;
      return;
    }
    const double s = std::clamp(w, 0.0, 1.0) * (n - 1);
    k = std::min(static_cast<int>(std::floor(s)), n - 2);
    f = s - k;
  };
  int i = 0, j = 0;
  double fu = 0, fv = 0;
  cell(nu, u, i, fu);
  cell(nv, v, j, fv);
  const int i1 = std::min(i + 1, nu - 1), j1 = std::min(j + 1, nv - 1);
  return (1 - fu) * (1 - fv) * x.col(j * nu + i) + fu * (1 - fv) * x.col(j * nu + i1) +
         (1 - fu) * fv * x.col(j1 * nu + i) + fu * fv * x.col(j1 * nu + i1);
}

double material_rms_distance(const cloth::Matrix3X& a, int a_nu, int a_nv, const cloth::Matrix3X& b,
                             int b_nu, int b_nv) {
  double sum = 0;
  for (int j = 0; j < a_nv; ++j)
    for (int i = 0; i < a_nu; ++i) {
      const double u = a_nu > 1 ? double(i) / (a_nu - 1) : 0.0;
      const double v = a_nv > 1 ? double(j) / (a_nv - 1) : 0.0;
      sum += (a.col(j * a_nu + i) - bilinear_position(b, b_nu, b_nv, u, v)).squaredNorm();
    }
  return std::sqrt(sum / double(a_nu * a_nv));
}

AccuracyReport run_accuracy(const Scenario& sc, const AccuracyOptions& o) {
  // options a user can get wrong
  if (o.out_dir.empty()) throw std::invalid_argument("accuracy: no output folder given");
  if (o.dts.empty() && o.halvings < 1)
    throw std::invalid_argument("--halvings " + std::to_string(o.halvings) +
                                ": expected at least 1 time step per engine");
  if (o.repeats < 1)
    throw std::invalid_argument("--repeats " + std::to_string(o.repeats) + ": expected >= 1");
  for (int r : o.resolutions)
    if (r < 2)
      throw std::invalid_argument("--resolutions: expected grids of at least 2 x 2, got " +
                                  std::to_string(r));
  for (size_t k = 0; k < sc.constraints.size(); ++k)
    if (!o.resolutions.empty() && sc.constraints[k].select == "indices")
      throw std::invalid_argument(
          "--resolutions: constraint " + std::to_string(k) + " of " + sc.source +
          " selects particles by grid indices, which do not carry over to another grid (select "
          "them by corners, edge:... or disk to compare resolutions)");
  const std::vector<EngineSpec> engines = selected_engines(sc, o);
  const std::vector<std::string> integrators = selected_integrators(o);
  const int jobs = std::max(1, o.jobs);
  // a scene an engine refuses fails here, before any work
  for (const EngineSpec& e : engines) require_engine_can_model(e, sc.scene, "");

  // the time-step study: engine, then integrator, then dt from the largest
  std::vector<Config> configs;
  std::vector<std::string> dt_keys, res_keys, engine_names;
  double smallest_dt = kInf;
  for (const EngineSpec& e : engines) {
    engine_names.push_back(e.name);
    const std::vector<double> dts = swept_dts(sc, e, o);
    smallest_dt = std::min(smallest_dt, dts.back());
    const std::vector<std::string> own =
        e.kind == EngineKind::custom ? integrators : std::vector<std::string>{""};
    for (const std::string& integrator : own)
      for (double dt : dts) {
        Config c;
        c.spec = with_integrator_and_dt(e, integrator, dt);
        c.integrator = integrator;
        c.key = join_key(e.name, integrator, format_double(dt));
        c.rerun = rerun_overrides(c.spec);
        dt_keys.push_back(c.key);
        configs.push_back(std::move(c));
      }
  }

  // the reference: the custom engine with rk4 well below every swept dt
  const EngineSpec* base = reference_base(sc);
  EngineSpec base_spec;
  base_spec.name = base ? base->name : "reference";
  if (base) base_spec = *base;
  AccuracyReport report;
  report.tolerance = o.tolerance;
  AccuracyReference& ref = report.reference;
  ref.study = "dt";
  ref.engine = base ? base->name : "";
  ref.dt = smallest_dt / 4;
  ref.nu = sc.scene.cloth.nu;
  ref.nv = sc.scene.cloth.nv;
  check_divides(sc, ref.dt, "the reference");
  const EngineSpec ref_spec = with_integrator_and_dt(base_spec, "rk4", ref.dt);
  const EngineSpec floor_spec = with_integrator_and_dt(base_spec, "rk4", 2 * ref.dt);
  const std::string base_words =
      base ? "custom engine " + base->name + "'s options" : "default custom-engine options";
  ref.description = "rk4 at dt = " + format_double(ref.dt) + " s (smallest swept dt " +
                    format_double(smallest_dt) + " s / 4) on " + grid_name(ref.nu, ref.nv) +
                    " particles, " + base_words;

  // the resolution study: the scene again on square grids of the same size and mass
  std::vector<Scenario> grids;
  std::vector<int> sizes(o.resolutions);
  std::sort(sizes.begin(), sizes.end());
  sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
  const cloth::ClothParams& cp = sc.scene.cloth;
  const double total_mass = cp.total_mass > 0 ? cp.total_mass : cp.particle_mass * cp.nu * cp.nv;
  if (!sizes.empty()) {
    const std::string text = scenario_to_toml(sc);
    for (int r : sizes)
      grids.push_back(
          parse_scenario(text, sc.source + " on " + grid_name(r, r),
                         {"cloth.particles=[" + std::to_string(r) + ", " + std::to_string(r) + "]",
                          "cloth.total_mass=" + format_double(total_mass)}));
    for (size_t g = 0; g < grids.size(); ++g)
      for (const EngineSpec& e : engines) {
        const std::vector<std::string> own =
            e.kind == EngineKind::custom ? integrators : std::vector<std::string>{""};
        for (const std::string& integrator : own) {
          Config c;
          c.spec = with_integrator_and_dt(e, integrator, e.dt);
          c.integrator = integrator;
          c.grid = static_cast<int>(g);
          c.key = join_key(e.name, integrator, std::to_string(sizes[g] * sizes[g]));
          c.rerun = rerun_at_grid(c.spec, sizes[g], total_mass);
          configs.push_back(std::move(c));
        }
      }
    // canonical order: engine, integrator, then grids from the coarsest
    for (const EngineSpec& e : engines)
      for (const std::string& integrator :
           e.kind == EngineKind::custom ? integrators : std::vector<std::string>{""})
        for (int r : sizes) res_keys.push_back(join_key(e.name, integrator, std::to_string(r * r)));
    // rk4 at the smallest dt of either study (explicit --dts may lie above the engines' own)
    AccuracyReference& rr = report.resolution_reference;
    rr.study = "resolution";
    rr.engine = ref.engine;
    rr.dt = smallest_dt;
    for (const EngineSpec& e : engines) rr.dt = std::min(rr.dt, e.dt);
    rr.nu = rr.nv = sizes.back();
    rr.description = "rk4 at dt = " + format_double(rr.dt) +
                     " s (the smallest dt swept or run) on " + grid_name(rr.nu, rr.nv) +
                     " particles (the finest grid), " + base_words;
  }
  const EngineSpec res_ref_spec =
      with_integrator_and_dt(base_spec, "rk4", report.resolution_reference.dt);

  // the folder: an earlier sweep is only resumed when it ran the same scenario and reference
  make_directories(o.out_dir);
  const std::string dir = o.out_dir + "/";
  const std::string toml = scenario_to_toml(sc);
  const auto earlier_refs = o.resume ? read_references(dir + "reference.csv")
                                     : std::map<std::string, std::vector<std::string>>{};
  if (o.resume) {
    const std::string earlier = read_text(dir + "scenario.toml");
    if (!earlier.empty() && earlier != toml)
      throw std::runtime_error(dir +
                               "scenario.toml: cannot resume: the folder holds a sweep of "
                               "another scenario (or other --set overrides); run without "
                               "--resume or choose another output folder");
    check_resumable_reference(dir + "reference.csv", earlier_refs, ref);
    if (!grids.empty())
      check_resumable_reference(dir + "reference.csv", earlier_refs, report.resolution_reference);
    auto it = earlier_refs.find("dt");
    if (it != earlier_refs.end() && !it->second[5].empty())
      ref.error_floor = std::stod(it->second[5]);
  }
  // the folder holds this sweep alone: files of an earlier one that it would not rewrite go
  std::vector<std::string> stale;
  if (o.tolerance <= 0) stale = {"recommendation.csv", "resolution_recommendation.csv"};
  if (grids.empty()) stale.insert(stale.end(), {"resolution.csv", "resolution_recommendation.csv"});
  for (const std::string& f : stale) std::filesystem::remove(dir + f);
  {
    AtomicFile f(dir + "scenario.toml");
    f.write(toml);
    f.commit();
  }
  std::vector<AccuracyReference> refs = {ref};
  std::vector<std::string> ref_reruns = {base ? rerun_overrides(ref_spec) : ""};
  if (!grids.empty()) {
    refs.push_back(report.resolution_reference);
    ref_reruns.push_back(base ? rerun_at_grid(res_ref_spec, sizes.back(), total_mass) : "");
  }
  write_references(dir + "reference.csv", refs, ref_reruns);

  SweepTable wp(dir + "work_precision.csv", kWorkPrecisionHeader, 3, o.resume);
  std::unique_ptr<SweepTable> rt;
  if (!grids.empty())
    rt = std::make_unique<SweepTable>(dir + "resolution.csv", kResolutionHeader, 3, o.resume);
  const auto table_of = [&](const Config& c) -> SweepTable& { return c.grid < 0 ? wp : *rt; };

  // configurations identical but for the engine name run once, for every missing row
  std::vector<std::vector<size_t>> groups;
  {
    std::map<std::string, size_t> group_of;
    for (size_t i = 0; i < configs.size(); ++i) {
      if (table_of(configs[i]).done(configs[i].key)) {
        ++report.resumed;
        continue;
      }
      const std::string sig = signature(configs[i].spec, configs[i].grid);
      auto it = group_of.find(sig);
      if (it == group_of.end()) {
        group_of[sig] = groups.size();
        groups.push_back({i});
      } else {
        groups[it->second].push_back(i);
      }
    }
  }
  bool dt_missing = false, res_missing = false;
  for (const auto& g : groups) (configs[g.front()].grid < 0 ? dt_missing : res_missing) = true;

  // the references first: every error needs them
  const cloth::Model model = cloth::build_model(sc.scene);
  std::vector<cloth::Model> grid_models;
  for (const Scenario& g : grids) grid_models.push_back(cloth::build_model(g.scene));
  struct RefJob {
    const Scenario* scenario;
    const cloth::Model* model;
    EngineSpec spec;
    bool keep_positions;
    EngineRun run;
  };
  std::vector<RefJob> ref_jobs;
  int ref_index = -1, floor_index = -1, res_ref_index = -1;
  if (dt_missing || std::isnan(ref.error_floor)) {
    ref_index = static_cast<int>(ref_jobs.size());
    ref_jobs.push_back({&sc, &model, ref_spec, true, {}});
  }
  if (std::isnan(ref.error_floor)) {
    floor_index = static_cast<int>(ref_jobs.size());
    ref_jobs.push_back({&sc, &model, floor_spec, false, {}});
  }
  if (res_missing) {
    res_ref_index = static_cast<int>(ref_jobs.size());
    ref_jobs.push_back({&grids.back(), &grid_models.back(), res_ref_spec, false, {}});
  }
  double total_steps = 0;
  for (const RefJob& j : ref_jobs) total_steps += double(planned_steps(*j.scenario, j.spec));
  for (const auto& g : groups) {
    const Config& c = configs[g.front()];
    total_steps +=
        double(o.repeats) * double(planned_steps(c.grid < 0 ? sc : grids[size_t(c.grid)], c.spec));
  }
  Progress progress(total_steps, "steps", o.progress);
  std::mutex progress_mutex;
  if (ref_index >= 0) progress.line("reference: " + ref.description);
  if (res_ref_index >= 0)
    progress.line("resolution reference: " + report.resolution_reference.description);

  // run_engine draws the bar from its own thread: only one reference job may hold it, the
  // others count their steps once all are done
  const int ref_threads = std::min(jobs, static_cast<int>(ref_jobs.size()));
  run_parallel(static_cast<int>(ref_jobs.size()), jobs, [&](int i) {
    RefJob& j = ref_jobs[static_cast<size_t>(i)];
    Progress* live = i == 0 || ref_threads == 1 ? &progress : nullptr;
    j.run = run_engine(*j.scenario, j.spec, *j.model, live, j.keep_positions);
  });
  if (ref_threads > 1)
    for (size_t i = 1; i < ref_jobs.size(); ++i)
      progress.advance(double(planned_steps(*ref_jobs[i].scenario, ref_jobs[i].spec)),
                       "references");
  for (const RefJob& j : ref_jobs)
    if (!j.run.stable)
      throw std::runtime_error("the reference (rk4 at dt = " + format_double(j.spec.dt) + " s on " +
                               grid_name(j.scenario->scene.cloth.nu, j.scenario->scene.cloth.nv) +
                               " particles) blew up at t = " + format_double(j.run.blowup_t) +
                               " s: " + sc.source +
                               " is not stable even so; sweep smaller time steps (--dts)");
  // the reference's error floor: rk4 at twice its dt against it
  if (floor_index >= 0) {
    const EngineRun& f = ref_jobs[size_t(floor_index)].run;
    ref.error_floor =
        rms_distance(f.snapshots.back(), ref_jobs[size_t(ref_index)].run.snapshots.back());
    refs[0].error_floor = ref.error_floor;
    write_references(dir + "reference.csv", refs, ref_reruns);
  }
  const EngineRun* dt_ref = ref_index >= 0 ? &ref_jobs[size_t(ref_index)].run : nullptr;
  const EngineRun* res_ref = res_ref_index >= 0 ? &ref_jobs[size_t(res_ref_index)].run : nullptr;

  // every missing row: run its group's configuration, measure, append one row per member
  run_parallel(static_cast<int>(groups.size()), jobs, [&](int gi) {
    const std::vector<size_t>& members = groups[size_t(gi)];
    const Config& first = configs[members.front()];
    const bool dt_study = first.grid < 0;
    const Scenario& s = dt_study ? sc : grids[size_t(first.grid)];
    const cloth::Model& m = dt_study ? model : grid_models[size_t(first.grid)];
    const TimedRun t = timed_run(s, m, first.spec, o.repeats, dt_study);
    const EngineRun& run = t.run;
    const double per_sim_s = simulated_s(run) > 0 ? t.wall_s / simulated_s(run) : 0.0;
    double error_final = kInf, error_max = kInf;
    if (run.stable && dt_study) {
      // both runs log the same frame times
      if (run.positions.size() != dt_ref->positions.size())
        throw std::logic_error("accuracy: frame counts differ from the reference's");
      error_max = 0;
      for (size_t k = 0; k < run.positions.size(); ++k) {
        error_final = rms_distance(run.positions[k], dt_ref->positions[k]);
        error_max = std::max(error_max, error_final);
      }
    } else if (run.stable) {
      const int n = sizes[size_t(first.grid)], nr = sizes.back();
      error_final =
          material_rms_distance(run.snapshots.back(), n, n, res_ref->snapshots.back(), nr, nr);
    }
    for (size_t i : members) {
      const Config& c = configs[i];
      std::vector<std::string> f = split_csv_line(c.key);
      if (dt_study) {
        f.insert(f.end(), {run.stable ? "1" : "0", optional_double(error_final),
                           optional_double(error_max), format_double(t.wall_s),
                           format_double(per_sim_s), std::to_string(run.counters.force_evals),
                           std::to_string(run.counters.cg_iterations), c.rerun});
      } else {
        f.insert(f.end(),
                 {format_double(c.spec.dt), run.stable ? "1" : "0", optional_double(error_final),
                  format_double(per_sim_s), std::to_string(run.counters.force_evals),
                  std::to_string(run.counters.cg_iterations), c.rerun});
      }
      table_of(c).append(f);
    }
    std::lock_guard<std::mutex> lock(progress_mutex);
    report.runs += 1;
    progress.advance(double(o.repeats) * double(planned_steps(s, first.spec)),
                     first.spec.name + (first.integrator.empty() ? "" : " " + first.integrator));
  });

  // the tables in their fixed order, read back as the report's rows
  wp.finish(dt_keys);
  report.files.push_back(dir + "scenario.toml");
  report.files.push_back(dir + "reference.csv");
  report.files.push_back(dir + "work_precision.csv");
  for (const auto& f : rows_in_order(wp, dt_keys))
    report.rows.push_back(parse_work_precision_row(f, ref.nu * ref.nv));
  if (rt) {
    rt->finish(res_keys);
    report.files.push_back(dir + "resolution.csv");
    for (const auto& f : rows_in_order(*rt, res_keys))
      report.resolution_rows.push_back(parse_resolution_row(f));
  }

  // fitted order per engine and integrator, over the points above the reference's floor
  {
    CsvWriter w(dir + "convergence.csv", {"engine", "integrator", "order", "points"});
    for (size_t i = 0; i < report.rows.size();) {
      size_t end = i;
      ConvergenceFit fit;
      fit.engine = report.rows[i].engine;
      fit.integrator = report.rows[i].integrator;
      std::vector<double> dts, errors;
      for (; end < report.rows.size() && report.rows[end].engine == fit.engine &&
             report.rows[end].integrator == fit.integrator;
           ++end) {
        const AccuracyRow& r = report.rows[end];
        const bool above_floor = std::isnan(ref.error_floor) || r.error_final > ref.error_floor;
        if (r.stable && std::isfinite(r.error_final) && r.error_final > 0 && above_floor) {
          dts.push_back(r.dt);
          errors.push_back(r.error_final);
        }
      }
      fit.points = static_cast<int>(dts.size());
      fit.order = fitted_order(dts, errors);
      w.add(fit.engine).add(fit.integrator).add(optional_double(fit.order)).add(fit.points);
      w.end_row();
      report.convergence.push_back(fit);
      i = end;
    }
    w.commit();
    report.files.push_back(dir + "convergence.csv");
  }

  // the cheapest configuration within the tolerance, per engine and overall
  if (o.tolerance > 0) {
    report.recommendations =
        recommend_all(report.rows, engine_names, o.tolerance, &AccuracyRow::error_max);
    CsvWriter w(dir + "recommendation.csv", {"scope", "engine", "integrator", "dt", "error_max",
                                             "wall_s_per_sim_s", "tolerance", "cost"});
    for (const Recommendation& r : report.recommendations) {
      w.add(r.scope).add(r.engine);
      if (r.found)
        w.add(r.row.integrator).add(r.row.dt).add(r.row.error_max).add(r.row.wall_s_per_sim_s);
      else
        w.skip().skip().skip().skip();
      w.add(o.tolerance).add(optional_double(r.found ? counted_work(r.row) : kNaN)).end_row();
    }
    w.commit();
    report.files.push_back(dir + "recommendation.csv");
    if (rt) {
      report.resolution_recommendations = recommend_all(report.resolution_rows, engine_names,
                                                        o.tolerance, &AccuracyRow::error_final);
      CsvWriter rw(dir + "resolution_recommendation.csv",
                   {"scope", "engine", "integrator", "particles", "dt", "error_final",
                    "wall_s_per_sim_s", "tolerance", "cost"});
      for (const Recommendation& r : report.resolution_recommendations) {
        rw.add(r.scope).add(r.engine);
        if (r.found)
          rw.add(r.row.integrator)
              .add(r.row.particles)
              .add(r.row.dt)
              .add(r.row.error_final)
              .add(r.row.wall_s_per_sim_s);
        else
          rw.skip().skip().skip().skip().skip();
        rw.add(o.tolerance).add(optional_double(r.found ? counted_work(r.row) : kNaN)).end_row();
      }
      rw.commit();
      report.files.push_back(dir + "resolution_recommendation.csv");
    }
  }
  return report;
}

namespace {

std::string short_double(double v) {
  if (!std::isfinite(v)) return v > 0 ? "inf" : "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string config_name(const AccuracyRow& r) {
  return r.engine + (r.integrator.empty() ? "" : " " + r.integrator);
}

void summarise_recommendations(std::ostringstream& s, const std::vector<Recommendation>& recs,
                               double tolerance, const char* error_name, bool grid) {
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "\ncheapest %s within %s <= %s m (by counted work, force evaluations + %g x CG "
                "iterations; see --help):\n",
                grid ? "grid" : "configuration", error_name, short_double(tolerance).c_str(),
                kCgIterationCost);
  s << buf;
  for (const Recommendation& r : recs) {
    const bool overall = r.scope == "overall";
    const double err = grid ? r.row.error_final : r.row.error_max;
    // the engine is the scope's name unless the scope is overall
    std::string what = overall ? config_name(r.row) : r.row.integrator;
    if (grid) what += (what.empty() ? "" : " ") + std::to_string(r.row.particles) + " particles";
    what += (what.empty() ? "" : " ") + std::string("at dt = ") + short_double(r.row.dt) + " s";
    std::string line;
    if (r.found)
      line = what + ": " + error_name + " " + short_double(err) + " m, " +
             short_double(r.row.wall_s_per_sim_s) + " s per simulated s" +
             (r.row.integrator.empty()
                  ? std::string()
                  : ", " + short_double(counted_work(r.row)) + " particle force evaluations");
    else if (!r.row.engine.empty())
      line = "nothing meets the tolerance (most accurate: " + what + ", " + error_name + " " +
             short_double(err) + " m)";
    else
      line = "nothing meets the tolerance (no stable run)";
    std::snprintf(buf, sizeof buf, "  %-24s %s\n", overall ? "overall" : r.engine.c_str(),
                  line.c_str());
    s << buf;
  }
}

}  // namespace

std::string accuracy_summary(const AccuracyReport& report) {
  std::ostringstream s;
  char buf[400];
  s << "reference: " << report.reference.description;
  if (std::isfinite(report.reference.error_floor))
    s << "; its error floor " << short_double(report.reference.error_floor) << " m";
  s << "\n\n";
  std::snprintf(buf, sizeof buf, "%-24s %-17s %6s %7s %6s %12s %12s\n", "engine", "integrator",
                "order", "theory", "stable", "best_error", "at_dt");
  s << buf;
  for (const ConvergenceFit& f : report.convergence) {
    int stable = 0, total = 0;
    const AccuracyRow* best = nullptr;
    for (const AccuracyRow& r : report.rows) {
      if (r.engine != f.engine || r.integrator != f.integrator) continue;
      ++total;
      if (!r.stable) continue;
      ++stable;
      if (!best || r.error_max < best->error_max) best = &r;
    }
    const auto integrator = cloth::parse_integrator(f.integrator);
    const std::string theory =
        integrator ? std::to_string(cloth::integrator_order(*integrator)) : "";
    std::snprintf(buf, sizeof buf, "%-24s %-17s %6s %7s %6s %12s %12s\n", f.engine.c_str(),
                  f.integrator.empty() ? "-" : f.integrator.c_str(),
                  std::isnan(f.order) ? "-" : short_double(f.order).c_str(), theory.c_str(),
                  (std::to_string(stable) + "/" + std::to_string(total)).c_str(),
                  best ? short_double(best->error_max).c_str() : "-",
                  best ? short_double(best->dt).c_str() : "-");
    s << buf;
  }
  if (report.tolerance > 0)
    summarise_recommendations(s, report.recommendations, report.tolerance, "error_max", false);
  if (!report.resolution_reference.study.empty()) {
    s << "\nresolution reference: " << report.resolution_reference.description << "\n";
    std::snprintf(buf, sizeof buf, "%-24s %-17s %9s %10s %6s %12s\n", "engine", "integrator",
                  "particles", "dt", "stable", "error_final");
    s << buf;
    for (const AccuracyRow& r : report.resolution_rows) {
      std::snprintf(buf, sizeof buf, "%-24s %-17s %9d %10s %6s %12s\n", r.engine.c_str(),
                    r.integrator.empty() ? "-" : r.integrator.c_str(), r.particles,
                    short_double(r.dt).c_str(), r.stable ? "yes" : "no",
                    r.stable ? short_double(r.error_final).c_str() : "-");
      s << buf;
    }
    if (report.tolerance > 0)
      summarise_recommendations(s, report.resolution_recommendations, report.tolerance,
                                "error_final", true);
  }
  return s.str();
}

}  // namespace clothbench
