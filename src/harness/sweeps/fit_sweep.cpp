#include "harness/sweeps/fit_sweep.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <regex>
#include <sstream>

#include "format/number_format.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/io/staged_folder.hpp"
#include "harness/io/text_file.hpp"
#include "harness/io/toml_text.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/engine_metric.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/fabric_preset.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_overrides.hpp"
#include "harness/sweeps/fit_joint.hpp"
#include "harness/sweeps/fit_reach.hpp"

namespace clothbench {

namespace {

/// The metrics fitted through the bend stiffness (or the hinge's rigidity) when no --range
/// names a parameter; with tensile_stiffness, the metrics that have a default parameter. Each
/// is positive by definition: a length, a rigidity, a drape coefficient, a stiffness.
constexpr const char* kBendMetrics[] = {"bending_length", "bending_length_peirce",
                                        "flexural_rigidity", "drape_coefficient"};

bool is_bend_metric(const std::string& metric) {
  return std::find(std::begin(kBendMetrics), std::end(kBendMetrics), metric) !=
         std::end(kBendMetrics);
}

/// True for the metrics default_parameter maps to a parameter (on every engine).
bool has_default_parameter(const std::string& metric) {
  return is_bend_metric(metric) || metric == "tensile_stiffness";
}

/// The prefix of a parameter that is the engine's own key ("engine.klst").
constexpr const char* kEngineKey = "engine.";

/// The keys a parameter sets: "a+b" sets a and b.
std::vector<std::string> parameter_keys(const std::string& parameter) {
  std::vector<std::string> keys;
  std::stringstream ss(parameter);
  for (std::string k; std::getline(ss, k, '+');) keys.push_back(k);
  return keys;
}

/// The --set texts that give parameter the value v on the engine called engine.
std::vector<std::string> parameter_sets(const std::string& parameter, const std::string& engine,
                                        double v) {
  std::vector<std::string> sets;
  for (const std::string& k : parameter_keys(parameter))
    sets.push_back((k.rfind(kEngineKey, 0) == 0 ? "engine." + engine + "." + k.substr(7) : k) +
                   "=" + cloth::toml_double(v));
  return sets;
}

/// True when scene key applies to the cloth of engine e in s: a per-direction structural key
/// (structural_u, structural_v) only to a cloth with per-direction springs, the one structural
/// key only to one without, any other key always. A fit of a strip's structural_u so leaves
/// an isotropic cantilever's structural stiffness as it is, and the reverse.
bool key_applies(const std::string& key, const EngineSpec& e, const Scenario& s) {
  const bool per_direction =
      key == "cloth.stiffness.structural_u" || key == "cloth.stiffness.structural_v";
  if (!per_direction && key != "cloth.stiffness.structural") return true;
  return engine_scene(s, e).cloth.anisotropic() == per_direction;
}

/// o with --fabric's preset set on every scenario (cloth.fabric), as the runs and fitted files
/// have it.
FitOptions with_fabric(const FitOptions& o) {
  FitOptions out = o;
  if (!o.fabric.empty()) out.overrides.insert(out.overrides.begin(), "cloth.fabric=" + o.fabric);
  return out;
}

/// The value a parameter has in s for engine e, when the harness can say it.
std::optional<double> current_value(const std::string& parameter, const EngineSpec& e,
                                    const Scenario& s) {
  const cloth::ClothParams& c = engine_scene(s, e).cloth;
  const std::string k = parameter_keys(parameter).front();
  if (k == "cloth.stiffness.bend") return c.k_bend;
  if (k == "cloth.stiffness.structural") return c.k_structural;
  if (k == "cloth.stiffness.shear") return c.k_shear;
  if (k == "cloth.stiffness.structural_u") return c.k_structural;
  if (k == "cloth.stiffness.structural_v") return c.structural_v();
  if (k == "cloth.bending_rigidity") return c.bending_rigidity;
  if (k == "cloth.damping") return c.damping;
  if (k == "engine.klst") return e.bullet.klst;
  return std::nullopt;
}

/// The engine called name in s, or null.
const EngineSpec* find_engine(const Scenario& s, const std::string& name) {
  for (const EngineSpec& e : s.engines)
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace

std::vector<FitTarget> fabric_targets(const Fabric& f, const Scenario& s) {
  std::vector<FitTarget> out;
  if (s.test.kind == "cantilever" && f.bending_warp > 0.0)
    out.push_back(
        {"bending_length", std::cbrt(f.bending_warp / (f.areal_density * kStandardGravity))});
  if (s.test.kind == "strip-tensile" && f.tensile_warp)
    out.push_back({"tensile_stiffness", s.test.direction == "u"
                                            ? *f.tensile_warp
                                            : f.tensile_weft.value_or(*f.tensile_warp)});
  const auto names = metric_names(s);
  if (f.drape_coefficient &&
      std::find(names.begin(), names.end(), "drape_coefficient") != names.end())
    out.push_back({"drape_coefficient", *f.drape_coefficient});
  return out;
}

std::string default_parameter(const std::string& metric, const EngineSpec& e, const Scenario& s) {
  const cloth::ClothParams& c = engine_scene(s, e).cloth;
  const bool klst = e.kind == EngineKind::bullet_softbody &&
                    e.bullet.stiffness == reference::SoftbodyStiffness::klst;
  if (klst) return "engine.klst";
  if (is_bend_metric(metric))
    return c.bend_model == cloth::BendModel::hinge ? "cloth.bending_rigidity"
                                                   : "cloth.stiffness.bend";
  // a strip of a grid with per-direction springs: the ones along its direction
  if (metric == "tensile_stiffness" && c.anisotropic())
    return s.test.direction == "v" ? "cloth.stiffness.structural_v"
                                   : "cloth.stiffness.structural_u";
  if (metric == "tensile_stiffness")
    return e.kind == EngineKind::bullet_deformable && c.k_shear > 0
               ? "cloth.stiffness.structural+cloth.stiffness.shear"
               : "cloth.stiffness.structural";
  throw UserError("--target " + metric + ": no default parameter for this metric on engine " +
                  e.name + "; name one with --range KEY=LO:HI");
}

namespace {

/// One fit's context: the scenarios as loaded (every engine) and what has been fitted so far.
struct FitJob {
  FitOptions o;  // with_fabric's
  std::vector<Scenario> scenarios;
  std::vector<FitTarget> targets;       // the options' and the fabric's
  std::vector<size_t> target_scenario;  // per target, the scenario giving its metric
  FitOutcome outcome;
  // every metric of each run made, by scenario, engine and --set texts: a run is made once
  std::map<std::string, std::map<std::string, double>> memo;
  int runs = 0;  // runs made
};

/// Every metric of one run of engine on scenario k (by name, NaN where the run gives none),
/// with extra --set texts after the fitted ones. A run asked for again is not run again.
const std::map<std::string, double>& measure_all(FitJob& job, size_t k, const std::string& engine,
                                                 const std::vector<std::string>& extra) {
  std::vector<std::string> sets = job.o.overrides;
  for (const auto& [key, v] : job.outcome.fitted[engine]) {
    const auto more = parameter_sets(key, engine, v);
    sets.insert(sets.end(), more.begin(), more.end());
  }
  sets.insert(sets.end(), extra.begin(), extra.end());
  // a structural key of the other form than scenario k's cloth is not set there
  const Scenario& given = job.scenarios[k];
  if (const EngineSpec* e = find_engine(given, engine))
    sets.erase(std::remove_if(sets.begin(), sets.end(),
                              [&](const std::string& set) {
                                return !key_applies(set.substr(0, set.find('=')), *e, given);
                              }),
               sets.end());
  std::string memo_key = std::to_string(k) + "\n" + engine;
  for (const std::string& set : sets) memo_key += "\n" + set;
  if (const auto it = job.memo.find(memo_key); it != job.memo.end()) return it->second;
  Scenario sc = load_scenario(job.o.scenarios[k], sets, {engine});
  // the engine alone: the reference runs only when it is the one fitted
  sc.engines.erase(std::remove_if(sc.engines.begin(), sc.engines.end(),
                                  [&](const EngineSpec& e) { return e.name != engine; }),
                   sc.engines.end());
  sc.reference = engine;
  RunOptions ro;
  ro.progress = false;
  ro.keep_positions = sc.test.kind == "strip-tensile";  // its curve reads every frame
  const RunResult r = run_scenario(sc, ro);
  ++job.runs;
  std::map<std::string, double> values;
  for (const std::string& name : metric_names(sc))
    values[name] = engine_metric(r, r.runs.front(), name).value_or(NAN);
  return job.memo[memo_key] = std::move(values);
}

/// One metric of one run (measure_all).
double measure(FitJob& job, size_t k, const std::string& engine, const std::string& metric,
               const std::vector<std::string>& extra) {
  const std::map<std::string, double>& values = measure_all(job, k, engine, extra);
  const auto it = values.find(metric);
  return it == values.end() ? NAN : it->second;
}

/// The solver's options for target t of engine e (its parameter already in row).
FitSolverOptions solver_options(FitJob& job, size_t t, const EngineSpec& e, const FitRow& row) {
  const FitOptions& o = job.o;
  FitSolverOptions so;
  so.target = job.targets[t].value;
  so.relative = job.targets[t].metric != "drape_coefficient";
  so.tolerance = so.relative ? o.tolerance : kDrapeTolerance;
  so.max_runs = o.max_runs;
  if (t < o.ranges.size()) {
    so.lo = o.ranges[t].lo;
    so.hi = o.ranges[t].hi;
  }
  // a link stiffness is a fraction of a full projection
  if (row.parameter == "engine.klst") {
    so.hi = std::min(so.hi, 1.0);
    if (so.lo == 0.0) so.lo = 1e-6;
  }
  // the start: what an earlier target fitted, else the scene's value, else mid-range
  std::optional<double> start;
  for (const auto& [key, v] : job.outcome.fitted[e.name])
    if (key == row.parameter) start = v;
  if (!start) start = current_value(row.parameter, e, job.scenarios[row.scenario]);
  if (!start || !(*start > 0.0)) {
    if (!(so.lo > 0.0) || !std::isfinite(so.hi))
      throw UserError("--range: " + row.parameter + " on engine " + e.name +
                      " has no positive value in the scenario to start from; give its range "
                      "with --range " +
                      row.parameter + "=LO:HI");
    start = std::sqrt(so.lo * so.hi);
  }
  so.start = std::clamp(*start, so.lo > 0.0 ? so.lo : *start, so.hi);
  return so;
}

/// The progress line of one run: parameter value, metric and target.
void show_run(const FitJob& job, const FitRow& row, int n, double p, double m) {
  if (!job.o.progress) return;
  char line[256];
  std::snprintf(line, sizeof line, "fit %s %s: run %d, %s = %.4g -> %.4g (target %.4g)\n",
                row.engine.c_str(), row.metric.c_str(), n, row.parameter.c_str(), p, m, row.target);
  std::cerr << line << std::flush;
}

/// The row of target t on engine before any run: its parameter, or status "no engine", or
/// "unreachable" when the scenario cannot show the target at any parameter (fit_reach.hpp).
FitRow new_row(FitJob& job, const std::string& engine, size_t t) {
  const FitTarget& target = job.targets[t];
  FitRow row;
  row.engine = engine;
  row.metric = target.metric;
  row.target = target.value;
  row.scenario = job.target_scenario[t];
  row.achieved = row.sensitivity = NAN;
  const Scenario& s = job.scenarios[row.scenario];
  const EngineSpec* e = find_engine(s, engine);
  if (!e) {
    row.status = "no engine";
    row.note = s.source + " has no engine " + engine;
    return row;
  }
  row.parameter =
      t < job.o.ranges.size() ? job.o.ranges[t].key : default_parameter(target.metric, *e, s);
  const FitSolverOptions so = solver_options(job, t, *e, row);
  row.value = so.start;
  const double tol = so.relative ? so.tolerance * std::abs(so.target) : so.tolerance;
  if (const auto why = unmeasurable_target(row.metric, row.target, tol, s)) {
    row.status = fit_status_name(FitStatus::unreachable);
    row.note = *why;
  }
  return row;
}

/// Fits target t on engine alone by the monotone solver; fills row (from new_row).
void fit_one(FitJob& job, FitRow& row, size_t t) {
  const std::string& engine = row.engine;
  const FitSolverOptions so =
      solver_options(job, t, *find_engine(job.scenarios[row.scenario], engine), row);
  int n = 0;
  const int runs_before = job.runs;
  const auto metric = [&](double p) {
    const double m =
        measure(job, row.scenario, engine, row.metric, parameter_sets(row.parameter, engine, p));
    show_run(job, row, ++n, p, m);
    return m;
  };
  const FitResult r = solve_monotone(metric, so);
  row.value = r.parameter;
  row.achieved = r.metric;
  row.runs += job.runs - runs_before;
  row.sensitivity = r.sensitivity;
  row.status = fit_status_name(r.status);
  row.note = r.note;
}

/// The targets with the fabric's added for the metrics the scenarios give and targets lacks.
std::vector<FitTarget> all_targets(const FitOptions& o, const std::vector<Scenario>& scenarios) {
  std::vector<FitTarget> targets = o.targets;
  if (o.fabric.empty()) return targets;
  const Fabric* f = shipped_fabrics().find(o.fabric);
  if (!f) {
    std::string names;
    for (const std::string_view n : shipped_fabrics().names())
      names += (names.empty() ? "" : ", ") + std::string(n);
    throw UserError("--fabric " + o.fabric + ": no such fabric (the presets: " + names + ")");
  }
  for (const Scenario& s : scenarios)
    for (const FitTarget& t : fabric_targets(*f, s))
      if (std::none_of(targets.begin(), targets.end(),
                       [&](const FitTarget& given) { return given.metric == t.metric; }))
        targets.push_back(t);
  return targets;
}

/// Loads the scenarios and finds the one that gives each target's metric.
void plan(FitJob& job) {
  std::vector<std::string> files;
  for (const std::string& path : job.o.scenarios) {
    job.scenarios.push_back(load_scenario(path, job.o.overrides));
    // each gives fitted/<its file name>
    const std::string name = std::filesystem::path(path).filename().string();
    if (std::find(files.begin(), files.end(), name) != files.end())
      throw UserError(path + ": another scenario has the file name " + name +
                      "; the fitted files would collide in fitted/");
    files.push_back(name);
  }
  job.targets = all_targets(job.o, job.scenarios);
  if (job.targets.empty())
    throw UserError("--fabric " + job.o.fabric +
                    ": the fabric has no value for any metric the scenarios give");
  for (const FitTarget& t : job.targets) {
    std::string given;
    size_t k = 0;
    for (; k < job.scenarios.size(); ++k) {
      const auto names = metric_names(job.scenarios[k]);
      if (std::find(names.begin(), names.end(), t.metric) != names.end()) break;
      for (const std::string& n : names) given += (given.empty() ? "" : ", ") + n;
    }
    if (k == job.scenarios.size())
      throw UserError("--target " + t.metric + ": none of the scenarios gives " + t.metric +
                      (given.empty() ? " (they give no metric)" : " (they give " + given + ")"));
    job.target_scenario.push_back(k);
  }
}

/// Refuses a metric given two targets (the fit could meet at most one) and, for the metrics
/// with a default parameter, a target that is not positive (a length, a rigidity, a tensile
/// stiffness and a drape coefficient are; the reach check would give advice for a negative).
void check_targets(const FitJob& job) {
  for (size_t t = 0; t < job.o.targets.size(); ++t) {
    const FitTarget& a = job.o.targets[t];
    for (size_t u = 0; u < t; ++u)
      if (job.o.targets[u].metric == a.metric)
        throw UserError("--target " + a.metric + ": given twice (" +
                        format_double(job.o.targets[u].value) + " and " + format_double(a.value) +
                        "); a metric has one target");
    if (has_default_parameter(a.metric) && !(a.value > 0.0))
      throw UserError("--target " + a.metric + "=" + format_double(a.value) +
                      ": expected a number > 0 (" + a.metric + " is positive)");
  }
}

/// Each --range key set once, at its LO, on its target's scenario for every engine fitted, so
/// that a key the scenario does not have is refused naming --range before any run.
void check_range_keys(const FitJob& job, const std::vector<std::string>& engines) {
  for (size_t t = 0; t < job.o.ranges.size() && t < job.targets.size(); ++t) {
    const FitRange& r = job.o.ranges[t];
    const std::string path = job.o.scenarios[job.target_scenario[t]];
    for (const std::string& engine : engines) {
      if (!find_engine(job.scenarios[job.target_scenario[t]], engine)) continue;
      for (const std::string& set : parameter_sets(r.key, engine, r.lo)) {
        std::vector<std::string> sets = job.o.overrides;
        sets.push_back(set);
        try {
          load_scenario(path, sets, {engine});
        } catch (const UserError& e) {
          throw UserError(as_option_error(
              e.what(), set.substr(0, set.find('=')),
              "--range " + r.key + "=" + format_double(r.lo) + ":" + format_double(r.hi)));
        }
      }
    }
  }
}

/// The engines to fit: the ones asked for (each in some scenario), else every engine.
std::vector<std::string> engines_to_fit(const FitJob& job) {
  std::vector<std::string> all;
  for (const Scenario& s : job.scenarios)
    for (const EngineSpec& e : s.engines)
      if (std::find(all.begin(), all.end(), e.name) == all.end()) all.push_back(e.name);
  for (const std::string& name : job.o.engines)
    if (std::find(all.begin(), all.end(), name) == all.end())
      throw UserError("--engine " + name + ": no scenario has an engine of that name");
  return job.o.engines.empty() ? all : job.o.engines;
}

/// The fitted value of parameter for engine, replacing an earlier one.
void keep_fitted(FitOutcome& outcome, const std::string& engine, const std::string& parameter,
                 double v) {
  auto& fitted = outcome.fitted[engine];
  for (auto& [key, value] : fitted)
    if (key == parameter) {
      value = v;
      return;
    }
  fitted.emplace_back(parameter, v);
}

}  // namespace

namespace {

/// True when row's achieved metric is within the tolerance of its target.
bool within(const FitOptions& o, const FitRow& row) {
  const double tol =
      row.metric == "drape_coefficient" ? kDrapeTolerance : o.tolerance * std::abs(row.target);
  return std::abs(row.achieved - row.target) <= tol;
}

/// The joint problem of rows[active] on one engine: its distinct parameters (each with the
/// range and start of the first target naming it) and the targets' tolerances.
JointFitOptions joint_options(FitJob& job, const std::vector<FitRow>& rows,
                              const std::vector<size_t>& active) {
  JointFitOptions jo;
  std::vector<double> target, tolerance, start, lo, hi;
  for (const size_t t : active) {
    const FitRow& row = rows[t];
    const FitSolverOptions so =
        solver_options(job, t, *find_engine(job.scenarios[row.scenario], row.engine), row);
    target.push_back(so.target);
    tolerance.push_back(so.relative ? so.tolerance * std::abs(so.target) : so.tolerance);
    if (std::find(jo.names.begin(), jo.names.end(), row.parameter) != jo.names.end()) continue;
    jo.names.push_back(row.parameter);
    start.push_back(so.start);
    lo.push_back(so.lo > 0.0 ? so.lo : so.start / 1e4);
    hi.push_back(std::isfinite(so.hi) ? so.hi : so.start * 1e4);
  }
  const auto vec = [](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size())).eval();
  };
  jo.target = vec(target);
  jo.tolerance = vec(tolerance);
  jo.start = vec(start);
  jo.lo = vec(lo);
  jo.hi = vec(hi);
  jo.max_runs = job.o.max_runs;
  return jo;
}

/// The --set texts of the joint problem's parameters at p (#N) on engine.
std::vector<std::string> joint_sets(const JointFitOptions& jo, const std::string& engine,
                                    const Eigen::VectorXd& p) {
  std::vector<std::string> sets;
  for (Eigen::Index j = 0; j < p.size(); ++j) {
    const auto more = parameter_sets(jo.names[size_t(j)], engine, p[j]);
    sets.insert(sets.end(), more.begin(), more.end());
  }
  return sets;
}

/// The progress line of one joint evaluation: the parameters, then each metric and target.
void show_joint_run(const FitJob& job, const std::string& engine, const JointFitOptions& jo, int n,
                    const Eigen::VectorXd& p, const std::vector<FitRow*>& rows,
                    const Eigen::VectorXd& m) {
  if (!job.o.progress) return;
  std::ostringstream line;
  line.precision(4);
  line << "fit " << engine << " joint: run " << n << ",";
  for (Eigen::Index j = 0; j < p.size(); ++j) line << " " << jo.names[size_t(j)] << " = " << p[j];
  line << " ->";
  for (size_t i = 0; i < rows.size(); ++i)
    line << (i ? ", " : " ") << rows[i]->metric << " = " << m[Eigen::Index(i)] << " (target "
         << rows[i]->target << ")";
  std::cerr << line.str() << "\n" << std::flush;
}

/// Fits rows[active] of one engine together (fit_joint.hpp): one evaluation runs each of
/// their scenarios once with every parameter set; fills the rows.
void fit_joint(FitJob& job, std::vector<FitRow>& rows, const std::vector<size_t>& active) {
  const std::string engine = rows[active.front()].engine;
  const JointFitOptions jo = joint_options(job, rows, active);
  std::vector<FitRow*> fit;
  for (const size_t t : active) fit.push_back(&rows[t]);
  int n = 0;
  const auto metrics = [&](const Eigen::VectorXd& p) {
    const std::vector<std::string> sets = joint_sets(jo, engine, p);
    Eigen::VectorXd m(Eigen::Index(fit.size()));
    for (size_t i = 0; i < fit.size(); ++i)
      m[Eigen::Index(i)] = measure(job, fit[i]->scenario, engine, fit[i]->metric, sets);
    show_joint_run(job, engine, jo, ++n, p, fit, m);
    return m;
  };
  const JointFitResult r = solve_joint(metrics, jo);
  for (size_t i = 0; i < fit.size(); ++i) {
    FitRow& row = *fit[i];
    const Eigen::Index j =
        std::find(jo.names.begin(), jo.names.end(), row.parameter) - jo.names.begin();
    row.value = r.parameters[j];
    row.achieved = r.metrics[Eigen::Index(i)];
    row.runs = int(r.samples.size());  // each a run of every scenario of the targets
    row.sensitivity = r.sensitivity(Eigen::Index(i), j);
    std::ostringstream all;
    all.precision(17);
    for (Eigen::Index k = 0; k < r.sensitivity.cols(); ++k)
      if (std::isfinite(r.sensitivity(Eigen::Index(i), k)))
        all << (all.tellp() > 0 ? " " : "") << jo.names[size_t(k)] << "="
            << r.sensitivity(Eigen::Index(i), k);
    row.sensitivities = all.str();
    const bool met = std::isfinite(row.achieved) && within(job.o, row);
    row.status = fit_status_name(met ? FitStatus::converged : r.status);
    row.note = met ? "within tolerance" : r.note;
  }
}

/// Runs engine at the joint fit's start for rows[active]; returns the targets whose metric has a
/// value there (the joint fit's first runs, remembered); the others' rows say they had none.
std::vector<size_t> given_at_start(FitJob& job, const std::string& engine,
                                   std::vector<FitRow>& rows, const std::vector<size_t>& active) {
  const JointFitOptions jo = joint_options(job, rows, active);
  const std::vector<std::string> start = joint_sets(jo, engine, jo.start);
  std::vector<size_t> given;
  for (const size_t t : active) {
    FitRow& row = rows[t];
    const int before = job.runs;
    row.achieved = measure(job, row.scenario, engine, row.metric, start);
    row.runs = job.runs - before;
    if (std::isfinite(row.achieved)) {
      given.push_back(t);
      continue;
    }
    row.status = fit_status_name(FitStatus::failed);
    row.note = "the engine gives no " + row.metric + " at the start";
  }
  return given;
}

/// Keeps the fitted value of every row of engine that has one.
void keep_rows(FitJob& job, const std::string& engine, const std::vector<FitRow>& rows) {
  for (const FitRow& row : rows)
    if (!row.parameter.empty() && row.status != "failed" && row.runs > 0)
      keep_fitted(job.outcome, engine, row.parameter, row.value);
}

/// Fits every target of engine: each one the scenario cannot show at all is unreachable at
/// once; the rest, one alone by the monotone solver, several together by the joint solver. A
/// target whose metric has no value at the joint fit's start (a cantilever too soft to measure)
/// is fitted alone afterwards, from the joint fit's values, when its parameter is its own.
void fit_engine(FitJob& job, const std::string& engine) {
  std::vector<FitRow> rows;
  std::vector<size_t> active, alone;
  for (size_t t = 0; t < job.targets.size(); ++t) {
    rows.push_back(new_row(job, engine, t));
    if (rows.back().status.empty()) active.push_back(t);
  }
  if (active.size() >= 2) {
    const std::vector<size_t> given = given_at_start(job, engine, rows, active);
    for (const size_t t : active) {
      const auto shares = [&](size_t g) { return rows[g].parameter == rows[t].parameter; };
      if (rows[t].status == "failed" && std::none_of(given.begin(), given.end(), shares))
        alone.push_back(t);
    }
    active = given;
  }
  if (active.size() == 1) fit_one(job, rows[active.front()], active.front());
  if (active.size() >= 2) fit_joint(job, rows, active);
  keep_rows(job, engine, rows);
  // each left out alone, with the values fitted so far (the monotone solver finds a start)
  for (const size_t t : alone) {
    fit_one(job, rows[t], t);
    if (rows[t].status != "failed")
      rows[t].note += " (fitted alone after the others: they were not measured again)";
    keep_rows(job, engine, {rows[t]});
  }
  job.outcome.rows.insert(job.outcome.rows.end(), rows.begin(), rows.end());
}

}  // namespace

FitOutcome run_fit(const FitOptions& o) {
  FitJob job{with_fabric(o), {}, {}, {}, {}, {}, 0};
  check_targets(job);
  plan(job);
  const std::vector<std::string> engines = engines_to_fit(job);
  check_range_keys(job, engines);
  for (const std::string& engine : engines) fit_engine(job, engine);
  return std::move(job.outcome);
}

namespace {

/// The [[engine]] tables of root, in file order.
std::vector<toml::table*> engine_tables(toml::table& root) {
  std::vector<toml::table*> out;
  if (toml::array* a = root["engine"].as_array())
    for (toml::node& n : *a)
      if (toml::table* t = n.as_table()) out.push_back(t);
  return out;
}

/// root's relative cloth.mesh made absolute against the scenario's folder.
void absolute_mesh(toml::table& root, const std::string& path) {
  toml::value<std::string>* mesh = root["cloth"]["mesh"].as_string();
  if (!mesh || std::filesystem::path(mesh->get()).is_absolute()) return;
  const std::filesystem::path folder = std::filesystem::absolute(path).parent_path();
  *mesh = (folder / mesh->get()).lexically_normal().string();
}

/// text with every float of 16 or more digits (how the TOML writer prints 0.2) shortened to
/// the shortest decimal that reads back as the same double.
std::string shortest_floats(const std::string& text) {
  static const std::regex long_float(R"([-+]?\d+\.\d{12,}(e[-+]?\d+)?)");
  std::string out;
  auto last = text.cbegin();
  for (std::sregex_iterator it(text.begin(), text.end(), long_float), end; it != end; ++it) {
    out.append(last, (*it)[0].first);
    out += cloth::toml_double(std::stod(it->str()));
    last = (*it)[0].second;
  }
  return out.append(last, text.cend());
}

}  // namespace

std::string fitted_scenario_text(const std::string& path, const FitOptions& given,
                                 const FitOutcome& outcome) {
  const FitOptions o = with_fabric(given);
  const Scenario s = load_scenario(path, o.overrides);
  toml::table root = toml::parse(read_existing_text(path), path);
  for (const std::string& set : o.overrides) apply_override(root, set);
  absolute_mesh(root, path);
  const std::vector<toml::table*> tables = engine_tables(root);
  for (size_t k = 0; k < tables.size() && k < s.engines.size(); ++k) {
    const auto it = outcome.fitted.find(s.engines[k].name);
    if (it == outcome.fitted.end()) continue;
    // scene keys into the engine's overrides, its own keys into its table
    toml::table& t = *tables[k];
    if (!t.contains("overrides")) t.insert("overrides", toml::table{});
    toml::table& own = *t["overrides"].as_table();
    own.is_inline(true);
    for (const auto& [parameter, v] : it->second)
      for (const std::string& key : parameter_keys(parameter)) {
        if (!key_applies(key, s.engines[k], s)) continue;
        if (key.rfind(kEngineKey, 0) == 0)
          t.insert_or_assign(key.substr(7), v);
        else
          own.insert_or_assign(key, v);
      }
    if (own.empty()) t.erase("overrides");
  }
  std::ostringstream text;
  text << "# " << std::filesystem::path(path).filename().string()
       << " with each engine's values fitted by clothbench fit (fit.csv beside this folder)\n"
       << root << "\n";
  return shortest_floats(text.str());
}

void write_fit(const FitOptions& o, const FitOutcome& outcome, const std::string& dir) {
  make_directories(dir);
  StagedFolder staged(dir);
  staged.owns("fitted");
  CsvWriter csv(staged.path() + "fit.csv", output_header("fit.csv"));
  for (const FitRow& r : outcome.rows) {
    csv.add(r.engine).add(r.parameter);
    // no run, no value: the engine is missing or the target unreachable before any run
    if (r.status == "no engine" || r.runs == 0)
      csv.skip();
    else
      csv.add(r.value);
    csv.add(r.metric).add(r.target);
    // undefined values stay empty
    for (const double v : {r.achieved, (r.achieved - r.target) / std::abs(r.target)})
      if (std::isfinite(v))
        csv.add(v);
      else
        csv.skip();
    csv.add(r.runs);
    if (std::isfinite(r.sensitivity))
      csv.add(r.sensitivity);
    else
      csv.skip();
    csv.add(r.sensitivities).add(r.status).end_row();
  }
  std::filesystem::create_directories(staged.path() + "fitted");
  std::vector<std::unique_ptr<AtomicFile>> files;
  for (const std::string& path : o.scenarios) {
    files.push_back(std::make_unique<AtomicFile>(staged.path() + "fitted/" +
                                                 std::filesystem::path(path).filename().string()));
    files.back()->write(fitted_scenario_text(path, o, outcome));
  }
  csv.commit();
  for (auto& f : files) f->commit();
  staged.commit();
}

}  // namespace clothbench
