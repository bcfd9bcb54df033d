#include "harness/gate/regression_check.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "format/number_format.hpp"
#include "harness/gate/ensemble_gate.hpp"
#include "harness/gate/ensemble_runs.hpp"
#include "harness/gate/ensemble_size.hpp"
#include "harness/gate/run_figures.hpp"
#include "harness/gate/test_metrics_gate.hpp"
#include "harness/gate/tolerances_file.hpp"
#include "harness/io/csv_reader.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/io/text_file.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/engine_metric.hpp"
#include "harness/run/run_parallel.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/stability/stability_sweep.hpp"
#include "harness/sweeps/sweep.hpp"

namespace clothbench {

namespace fs = std::filesystem;

namespace {

std::string read_file(const fs::path& p) {
  return read_existing_text(p.string());
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
      throw UserError(p.string() + ": [ungated." + engine + "] names an engine " + sc.name +
                      " does not have");
  for (const auto& [engine, e] : t.ensemble)
    if (!has(engine))
      throw UserError(p.string() + ": [ensemble." + engine + "] names an engine " + sc.name +
                      " does not have");
  for (const std::string& engine : t.mirrored)
    if (!has(engine))
      throw UserError(p.string() + ": [mirror] names engine " + engine + ", which " + sc.name +
                      " does not have");
  if (!t.mirrored.empty() && (sc.scene.mesh || sc.scene.cloth.nu < 2))
    throw UserError(p.string() + ": [mirror] needs a grid at least 2 particles wide" +
                    (sc.scene.mesh ? " (this scenario's cloth is a mesh)" : ""));
}

// why a quantity is not gated for engines of a kind (empty: it is gated)
std::string ungated_reason(EngineKind kind, const std::string& quantity) {
  const EngineKindInfo& info = engine_kind_info(kind);
  if (!info.energy_gated && quantity == "max_energy_error")
    return std::string("not gated: ") + info.energy_note;
  return "";
}

// every engine's [test] metrics (tests.csv), none for a scenario without a [test]
TestValues run_test_values(const RunResult& r) {
  TestValues values;
  for (const EngineRun& run : r.runs)
    for (const TestMetric& row : test_metrics(r, run))
      values[run.spec.name][row.metric] = row.value;
  return values;
}

using Metrics = std::map<std::string, double>;  // by "engine/quantity"
using Shapes = std::map<std::string, cloth::Matrix3X>;

// a baseline's stability limits: the search's bracket [stable_dt, first_unstable_dt)
struct Bracket {
  double stable_dt = 0;          // s, found stable
  double first_unstable_dt = 0;  // s, found unstable (infinity: none up to dt_max)
};
using Brackets = std::map<std::string, Bracket>;  // by "engine/integrator"

// the baseline files' columns (output_schema.cpp), as written and as read back
const std::vector<std::string> kMetricsHeader = output_header("baselines/metrics.csv");
const std::vector<std::string> kShapeHeader = output_header("baselines/shape.csv");
const std::vector<std::string> kStabilityHeader = output_header("baselines/stability.csv");

/// The recorded figures; strict: a row given twice, or an engine without a row for one of
/// kMetricQuantities (a damaged file, or one from another version), is an error naming the
/// file and line (--update reads an old baseline leniently: it rewrites it).
Metrics read_metrics(const fs::path& p, bool strict = true) {
  Metrics m;
  std::map<std::string, long> line_of;                 // engine/quantity -> its line
  std::map<std::string, std::pair<long, long>> lines;  // engine -> its first and last rows' lines
  for (const CsvRecord& r : read_csv(p.string(), kMetricsHeader).records) {
    const std::string key = r.text(0) + "/" + r.text(1);
    if (strict && line_of.count(key))
      throw UserError(p.string() + ":" + std::to_string(r.line()) + ": a second row for " +
                      r.text(0) + "," + r.text(1) + " (the first is line " +
                      std::to_string(line_of[key]) +
                      "); restore the file or record it again with check --update");
    line_of[key] = static_cast<long>(r.line());
    auto [it, added] = lines.try_emplace(r.text(0), r.line(), r.line());
    it->second.second = r.line();
    m[key] = r.number(2, NAN);
  }
  if (!strict) return m;
  for (const auto& [engine, span] : lines)
    for (const std::string& q : kMetricQuantities)
      if (!m.count(engine + "/" + q))
        throw UserError(p.string() + ": no row for " + engine + "," + q + " (" + engine +
                        "'s rows: lines " + std::to_string(span.first) + " to " +
                        std::to_string(span.second) +
                        "): the file is damaged or from another version of clothbench; restore "
                        "it or record it again with check --update");
  return m;
}

// every engine's final shape, 3 by #P (NaN for particles the file leaves out)
Shapes read_shapes(const fs::path& p, const cloth::Model& model) {
  Shapes shapes;
  const Eigen::Index np = model.particle_count();
  for (const CsvRecord& r : read_csv(p.string(), kShapeHeader).records) {
    auto& m = shapes[r.text(0)];
    if (m.cols() == 0) m = cloth::Matrix3X::Constant(3, np, NAN);
    const long i = std::lround(r.number(1, NAN)), j = std::lround(r.number(2, NAN));
    if (i < 0 || i >= model.nu || j < 0 || j >= model.nv)
      throw UserError(p.string() + ":" + std::to_string(r.line()) + ": particle (" + r.text(1) +
                      ", " + r.text(2) + ") outside the " + std::to_string(model.nu) + " x " +
                      std::to_string(model.nv) + " grid");
    for (int a = 0; a < 3; ++a) m(a, j * model.nu + i) = r.number(size_t(3 + a), NAN);
  }
  return shapes;
}

Brackets read_brackets(const fs::path& p) {
  Brackets b;
  for (const CsvRecord& r : read_csv(p.string(), kStabilityHeader).records)
    b[r.text(0) + "/" + r.text(1)] = {r.number(2, NAN), r.number(3, NAN)};
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

// the engine part of a "engine/quantity" key
std::string engine_of(const std::string& key) {
  return key.substr(0, key.rfind('/'));
}

double mean_of(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? NAN : sum / double(v.size());
}

// whether the tolerances gate this engine's quantity by its ensemble
bool in_ensemble(const Tolerances& tol, const std::string& engine, const std::string& q) {
  const auto it = tol.ensemble.find(engine);
  return it != tol.ensemble.end() && it->second.quantities.count(q);
}

void write_baseline(const fs::path& dir, const RunResult& result,
                    const std::vector<StabilityRow>* stability, const EnsembleValues& ensemble,
                    PendingBaselines& pending) {
  make_directories(dir.string());
  auto metrics = std::make_unique<CsvWriter>((dir / "metrics.csv").string(), kMetricsHeader);
  for (size_t i = 0; i < result.runs.size(); ++i)
    for (const auto& [q, v] : run_metrics(result, i))
      metrics->add(result.runs[i].spec.name).add(q).add(v).end_row();
  auto shape = std::make_unique<CsvWriter>((dir / "shape.csv").string(), kShapeHeader);
  for (const EngineRun& run : result.runs) {
    const cloth::Matrix3X& x = run.snapshots.back();
    for (Eigen::Index p = 0; p < x.cols(); ++p)
      shape->add(run.spec.name)
          .add(int(p % result.model.nu))
          .add(int(p / result.model.nu))
          .add(x(0, p))
          .add(x(1, p))
          .add(x(2, p))
          .end_row();
  }
  pending.add(std::move(metrics));
  pending.add(std::move(shape));
  // the [test]'s metrics, gated by tolerances.toml's [tests]
  const fs::path tests = dir / "tests.csv";
  if (result.scenario.test.kind.empty()) {
    pending.remove_on_commit(tests.string());
  } else {
    auto w = std::make_unique<CsvWriter>(tests.string(), output_header("baselines/tests.csv"));
    write_test_values(run_test_values(result), *w);
    pending.add(std::move(w));
  }
  if (stability) {
    auto st = std::make_unique<CsvWriter>((dir / "stability.csv").string(), kStabilityHeader);
    for (const StabilityRow& r : *stability)
      st->add(r.engine).add(r.integrator).add(r.stable_dt).add(r.first_unstable_dt).end_row();
    pending.add(std::move(st));
  } else {
    // limits no longer searched must not linger as a baseline nobody checks
    pending.remove_on_commit((dir / "stability.csv").string());
  }
  const fs::path ens = dir / "metrics_ensemble.csv";
  if (ensemble.empty()) {
    pending.remove_on_commit(ens.string());
    return;
  }
  auto w =
      std::make_unique<CsvWriter>(ens.string(), output_header("baselines/metrics_ensemble.csv"));
  write_ensemble(ensemble, *w);
  pending.add(std::move(w));
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

# with a [test]: one line per metric of its tests.csv (check names the missing ones), e.g.
# [tests]
# bending_length = { rel = 1e-6 }
)";

}  // namespace

ScratchFolder::ScratchFolder(const std::string& prefix) {
  const std::string pattern = (fs::temp_directory_path() / (prefix + "XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  if (!::mkdtemp(name.data()))
    throw UserError("cannot create a temporary folder " + pattern + ": " + std::strerror(errno));
  m_path = name.data();
}

ScratchFolder::~ScratchFolder() {
  std::error_code ignored;  // nothing sensible to do about a folder that will not go
  fs::remove_all(m_path, ignored);
}

namespace {

/// What a check compares: the scenario, its baseline folder and its tolerances.
struct CheckPlan {
  Scenario sc;
  fs::path dir;  // the scenario's baseline folder
  Tolerances tol;
  fs::path metrics_path() const { return dir / "metrics.csv"; }
  fs::path shape_path() const { return dir / "shape.csv"; }
  fs::path stability_path() const { return dir / "stability.csv"; }
};

/// What the scenario does now: its run, its stability limits when they are gated, and the
/// members' values of its ensembles when they run.
struct CheckRun {
  RunResult result;
  std::vector<StabilityRow> stability;
  Brackets brackets;
  EnsembleValues ensemble;
  std::map<std::string, EnsembleChoice> choices;  // update: how the sizes were chosen
};

/// The alpha of each of the scenario's ensemble rows: kEnsembleFalseAlarm over them all.
double ensemble_alpha(const Tolerances& tol) {
  size_t rows = 0;
  for (const auto& [engine, e] : tol.ensemble) rows += e.quantities.size();
  return kEnsembleFalseAlarm / double(rows);
}

/// The ensembles' values: member 0 is now.result, members 1.. run on o.jobs threads (their
/// engines and the reference only); final_shape_rms is measured from shapes (the recorded
/// ones, or member 0's for an update). A check runs the recorded or fixed sizes; an update
/// chooses the sizes of the ensembles with `detect` (ensemble_runs.hpp).
void run_ensembles(const CheckPlan& plan, const EngineShapes& shapes, const CheckOptions& o,
                   CheckRun& now) {
  EnsembleMembers members(plan.sc, plan.tol, now.result, shapes, o.jobs, o.ensemble_seed);
  EnsembleSizes sizes;
  if (o.update) {
    now.choices = choose_sizes(members, plan.tol, ensemble_alpha(plan.tol), o.progress, sizes);
  } else {
    const fs::path recorded = plan.dir / "metrics_ensemble.csv";
    sizes = recorded_sizes(
        plan.tol, fs::exists(recorded) ? read_ensemble(recorded.string()) : EnsembleValues());
    members.run_up_to(sizes);
  }
  now.ensemble = members.values(sizes);
}

/// Refuses a perturbed update, loads the scenario and its tolerances (writing the template
/// first for a new baseline).
CheckPlan plan_check(const std::string& scenario_path, const CheckOptions& o) {
  // std::invalid_argument, not UserError: the regression tests expect this type
  if (o.update && !o.overrides.empty() && !o.record_perturbed)
    throw UserError(
        "--update with --set would record a perturbed engine as the baseline, which then hides "
        "the very change it should catch; drop the --set overrides, or add --record-perturbed "
        "if a perturbed baseline is what you mean");
  CheckPlan plan{load_scenario(scenario_path, o.overrides), {}, {}};
  plan.sc.max_run_seconds = o.max_run_seconds;
  plan.dir = fs::path(o.baseline_dir) / plan.sc.name;
  const fs::path tol_path = plan.dir / "tolerances.toml";
  if (o.update && !fs::exists(tol_path)) {
    make_directories(plan.dir.string());
    AtomicFile f(tol_path.string());
    f.write(kToleranceTemplate);
    f.commit();
  }
  if (!fs::exists(tol_path))
    throw UserError("no baseline for scenario " + plan.sc.name + ": " + tol_path.string() +
                    " is missing (record one with clothbench check --update)");
  plan.tol = read_tolerances(tol_path);
  check_tolerance_engines(plan.tol, plan.sc, tol_path);
  // a damaged baseline is an error before any run, not a failing gate after it
  if (!o.update && fs::exists(plan.metrics_path())) read_metrics(plan.metrics_path());
  if (!o.update && fs::exists(plan.dir / "tests.csv")) read_test_values(plan.dir / "tests.csv");
  return plan;
}

CheckRun run_check(const CheckPlan& plan, const CheckOptions& o) {
  CheckRun now;
  RunOptions ro;
  ro.progress = o.progress;
  now.result = run_scenario(plan.sc, ro);
  if (plan.tol.stability) {
    // the search writes its table to a folder of its own, gone on every way out of this block
    const ScratchFolder scratch("clothbench-check-" + plan.sc.name + "-");
    StabilityOptions so;
    so.out_dir = scratch.path();
    so.engines = {plan.tol.stability_engine};
    so.integrators = plan.tol.stability_integrators;
    so.rel_tol = plan.tol.stability_rel_tol;
    so.jobs = o.jobs;
    so.progress = o.progress;
    so.method = StabilityMethod::blowup;  // the baselines gate the blow-up limits
    now.stability = run_stability(plan.sc, so);
  }
  now.brackets = brackets_of(now.stability);
  if ((o.update || o.ensemble) && !plan.tol.ensemble.empty()) {
    // an update measures shapes from its own member 0, a check from the recorded shapes
    Shapes shapes;
    if (o.update)
      for (const EngineRun& run : now.result.runs) shapes[run.spec.name] = run.snapshots.back();
    else
      shapes = read_shapes(plan.shape_path(), now.result.model);
    run_ensembles(plan, shapes, o, now);
  }
  return now;
}

/// What --update changed in the test metrics: new, updated and removed rows.
void test_changes(const std::string& scenario, const TestValues& before, const TestValues& after,
                  std::vector<Gate>& gates) {
  auto same = [](double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); };
  for (const auto& [engine, rows] : after)
    for (const auto& [metric, v] : rows) {
      const auto e = before.find(engine);
      const bool had = e != before.end() && e->second.count(metric);
      const double b = had ? e->second.at(metric) : NAN;
      if (!had || !same(b, v))
        gates.push_back({scenario, engine, "test." + metric, b, v, std::abs(v - b), NAN, true,
                         had ? "updated" : "new", "-"});
    }
  for (const auto& [engine, rows] : before)
    for (const auto& [metric, b] : rows) {
      const auto e = after.find(engine);
      if (e == after.end() || !e->second.count(metric))
        gates.push_back(
            {scenario, engine, "test." + metric, b, NAN, NAN, NAN, true, "removed", "-"});
    }
}

/// What an update says of one recorded ensemble row: its size and, where it was chosen, the
/// shift it catches against the goal and whether the time cap held it back.
std::string recorded_note(const std::string& key, const std::vector<double>& v,
                          const std::map<std::string, EnsembleChoice>& choices,
                          const Tolerances& tol) {
  std::string note = "ensemble of " + std::to_string(v.size()) + " recorded";
  const auto c = choices.find(engine_of(key));
  const std::string q = key.substr(key.rfind('/') + 1);
  if (c == choices.end() || !c->second.detectable.count(q)) return note;
  const Tolerances::Ensemble& e = tol.ensemble.at(c->first);
  note += ": catches a shift of " + note_number(c->second.detectable.at(q)) + " (goal " +
          note_number(e.detect.at(q)) + ")";
  if (c->second.capped)
    note += "; more members would cost over max_seconds = " + note_number(e.max_seconds) + " s (" +
            note_number(c->second.member_seconds) + " s a member)";
  return note;
}

/// --update: records the baseline and reports what changed against the previous one.
std::vector<Gate> record(const CheckPlan& plan, const CheckRun& now, const CheckOptions& o) {
  const Metrics old_metrics =
      fs::exists(plan.metrics_path()) ? read_metrics(plan.metrics_path(), false) : Metrics();
  Shapes old_shapes;
  std::string grid_changed;
  try {
    if (fs::exists(plan.shape_path()))
      old_shapes = read_shapes(plan.shape_path(), now.result.model);
  } catch (const UserError& e) {
    grid_changed = e.what();  // a grid of another size: no shape to compare with
  }
  const Brackets old_brackets =
      fs::exists(plan.stability_path()) ? read_brackets(plan.stability_path()) : Brackets();
  PendingBaselines own;
  const fs::path ens_path = plan.dir / "metrics_ensemble.csv";
  const EnsembleValues old_ensemble =
      fs::exists(ens_path) ? read_ensemble(ens_path.string()) : EnsembleValues();
  const fs::path tests_path = plan.dir / "tests.csv";
  const TestValues old_tests = fs::exists(tests_path) ? read_test_values(tests_path) : TestValues();
  write_baseline(plan.dir, now.result, plan.tol.stability ? &now.stability : nullptr, now.ensemble,
                 o.pending ? *o.pending : own);
  own.commit();
  std::vector<Gate> gates =
      changes(plan.sc.name, old_metrics, old_shapes, old_brackets, now.result, now.brackets);
  test_changes(plan.sc.name, old_tests, run_test_values(now.result), gates);
  for (const auto& [key, v] : now.ensemble) {
    const auto it = old_ensemble.find(key);
    if (it == old_ensemble.end() || it->second != v)
      gates.push_back({plan.sc.name, engine_of(key), key.substr(key.rfind('/') + 1) + " (mean)",
                       it == old_ensemble.end() ? NAN : mean_of(it->second), mean_of(v), NAN, NAN,
                       true, recorded_note(key, v, now.choices, plan.tol), "-"});
  }
  if (!grid_changed.empty())
    gates.push_back({plan.sc.name, "", "final_shape_rms", NAN, NAN, NAN, NAN, true,
                     "previous shapes not comparable: " + grid_changed, "-"});
  return gates;
}

/// The gates of one scenario, added as the comparison goes.
class GateList {
 public:
  explicit GateList(std::string scenario) : m_scenario(std::move(scenario)) {}

  /// A gated quantity: passes when within allowed (or missing on both sides).
  void gate(const std::string& engine, const std::string& quantity, double base, double now,
            double allowed, double difference) {
    Gate g{m_scenario, engine, quantity, base, now, difference, allowed, true, "", ""};
    const bool both_nan = std::isnan(base) && std::isnan(now);
    g.pass = both_nan || difference <= allowed;
    if (!g.pass) g.note = std::isnan(difference) ? "one side is missing" : "moved";
    m_gates.push_back(g);
  }
  /// A quantity that fails whatever its value, for the reason why.
  void fail(const std::string& engine, const std::string& quantity, double base, double now,
            const std::string& why) {
    m_gates.push_back({m_scenario, engine, quantity, base, now, NAN, 0, false, why, ""});
  }
  /// A quantity shown for the record only.
  void ungated(const std::string& engine, const std::string& quantity, double base, double now,
               double difference, const std::string& why) {
    m_gates.push_back(
        {m_scenario, engine, quantity, base, now, difference, NAN, true, why, "-", false});
  }
  void add(const Gate& g) { m_gates.push_back(g); }
  const std::string& scenario() const { return m_scenario; }
  std::vector<Gate>& gates() { return m_gates; }

 private:
  std::string m_scenario;
  std::vector<Gate> m_gates;
};

/// Every engine recorded must have run and every one that ran must have a baseline; returns
/// the recorded ones.
std::set<std::string> compare_engines(const Metrics& base, const Shapes& shapes,
                                      const RunResult& result, GateList& gates) {
  std::set<std::string> recorded, ran;
  for (const auto& [key, v] : base) recorded.insert(engine_of(key));
  for (const auto& [engine, x] : shapes) recorded.insert(engine);
  for (const EngineRun& run : result.runs) ran.insert(run.spec.name);
  for (const std::string& engine : recorded)
    if (!ran.count(engine))
      gates.fail(engine, "ran", 1, 0, "recorded in the baseline but did not run");
  for (const std::string& engine : ran)
    if (!recorded.count(engine))
      gates.fail(engine, "ran", 0, 1, "ran but has no baseline (record one with --update)");
  return recorded;
}

void compare_metrics(const Metrics& base, const std::set<std::string>& recorded,
                     const Tolerances& tol, const RunResult& result, bool ensembles_ran,
                     GateList& gates) {
  for (size_t i = 0; i < result.runs.size(); ++i) {
    const EngineSpec& spec = result.runs[i].spec;
    if (!recorded.count(spec.name)) continue;
    const auto now = run_metrics(result, i);
    for (const std::string& q : kMetricQuantities) {
      const auto it = base.find(spec.name + "/" + q);
      if (it == base.end()) {
        gates.fail(spec.name, q, NAN, now.at(q), "not in the baseline");
        continue;
      }
      const double b = it->second, v = now.at(q);
      // an ensemble row replaces the single run's, or is shown for the record
      if (in_ensemble(tol, spec.name, q)) {
        if (!ensembles_ran) gates.ungated(spec.name, q, b, v, std::abs(v - b), kEnsembleElsewhere);
        continue;
      }
      const auto listed = tol.ungated.find(spec.name);
      const std::string why = listed != tol.ungated.end() && listed->second.count(q)
                                  ? "not gated: " + listed->second.at(q)
                                  : ungated_reason(spec.kind, q);
      if (!why.empty())
        gates.ungated(spec.name, q, b, v, std::abs(v - b), why);
      else
        gates.gate(spec.name, q, b, v, tol.quantity.at(q).allowed(b), std::abs(v - b));
    }
  }
}

void compare_shapes(const Shapes& shapes, const std::set<std::string>& recorded,
                    const Tolerances& tol, const RunResult& result, bool ensembles_ran,
                    GateList& gates) {
  for (const EngineRun& run : result.runs) {
    if (!recorded.count(run.spec.name)) continue;
    const auto it = shapes.find(run.spec.name);
    if (it == shapes.end()) {
      gates.fail(run.spec.name, "final_shape_rms", NAN, NAN, "no shape in the baseline");
      continue;
    }
    double rms = shape_rms(run.snapshots.back(), it->second);
    if (in_ensemble(tol, run.spec.name, "final_shape_rms")) {
      if (!ensembles_ran)
        gates.ungated(run.spec.name, "final_shape_rms", 0.0, rms, rms, kEnsembleElsewhere);
      continue;
    }
    const auto listed = tol.ungated.find(run.spec.name);
    if (listed != tol.ungated.end() && listed->second.count("final_shape_rms")) {
      gates.ungated(run.spec.name, "final_shape_rms", 0.0, rms, rms,
                    "not gated: " + listed->second.at("final_shape_rms"));
      continue;
    }
    bool mirrored = false;
    if (tol.mirrored.count(run.spec.name)) {
      // the engine may pick either side of the scene's symmetry: the nearer image counts
      const double m = shape_rms(run.snapshots.back(), mirror_image(it->second, result.model));
      mirrored = m < rms;
      rms = std::min(rms, m);
    }
    gates.gate(run.spec.name, "final_shape_rms", 0.0, rms,
               tol.quantity.at("final_shape_rms").allowed(0.0), rms);
    if (mirrored && gates.gates().back().pass) gates.gates().back().note = "to the mirror image";
  }
}

/// The two gates of one stability limit: the recorded search found the limit in
/// [stable_dt, first_unstable_dt); the same search now must bracket a limit that can be the
/// same one, so the two half-open brackets must overlap (an adjacent bracket means the run at
/// the shared dt changed verdict).
void compare_bracket(const std::string& key, const Bracket& b, const Bracket& n, bool adjacent,
                     GateList& gates) {
  const std::string miss =
      "now [" + format_double(n.stable_dt) + ", " + format_double(n.first_unstable_dt) +
      ") misses [" + format_double(b.stable_dt) + ", " + format_double(b.first_unstable_dt) + ")";
  // both ends fail together: the two brackets cannot hold the same limit (with adjacent,
  // brackets that share an end may: the run at that dt turned the other way)
  const bool overlap =
      adjacent ? n.stable_dt <= b.first_unstable_dt && b.stable_dt <= n.first_unstable_dt
               : n.stable_dt < b.first_unstable_dt && b.stable_dt < n.first_unstable_dt;
  gates.add({gates.scenario(), key, "stable_dt", b.stable_dt, n.stable_dt,
             std::abs(n.stable_dt - b.stable_dt), NAN, overlap, overlap ? "" : miss,
             "< " + format_double(b.first_unstable_dt)});
  const double d = std::isinf(b.first_unstable_dt) && b.first_unstable_dt == n.first_unstable_dt
                       ? 0.0
                       : std::abs(n.first_unstable_dt - b.first_unstable_dt);
  gates.add({gates.scenario(), key, "first_unstable_dt", b.first_unstable_dt, n.first_unstable_dt,
             d, NAN, overlap, overlap ? "" : miss, "> " + format_double(b.stable_dt)});
}

void compare_stability(const CheckPlan& plan, const Brackets& now, GateList& gates) {
  const fs::path stpath = plan.stability_path();
  const Brackets recorded = fs::exists(stpath) ? read_brackets(stpath) : Brackets();
  if (!plan.tol.stability) {
    for (const auto& [key, b] : recorded)
      gates.fail(key, "stable_dt", b.stable_dt, NAN,
                 "recorded, but tolerances.toml has no [stability] table to search it");
    return;
  }
  if (!fs::exists(stpath)) read_file(stpath);  // throws, naming the missing file
  for (const auto& [key, b] : recorded)
    if (!now.count(key))
      gates.fail(key, "stable_dt", b.stable_dt, NAN, "recorded in the baseline but not searched");
  for (const auto& [key, n] : now) {
    const auto it = recorded.find(key);
    if (it == recorded.end())
      gates.fail(key, "stable_dt", NAN, n.stable_dt, "searched but has no baseline");
    else
      compare_bracket(key, it->second, n, plan.tol.stability_adjacent, gates);
  }
}

/// The ensemble rows: each listed quantity by Welch's test at kEnsembleFalseAlarm over the
/// scenario's rows, and each engine's growth exponent for the record.
void compare_ensembles(const CheckPlan& plan, const CheckRun& now,
                       const std::set<std::string>& recorded, GateList& gates) {
  const double alpha = ensemble_alpha(plan.tol);
  const EnsembleValues base = read_ensemble((plan.dir / "metrics_ensemble.csv").string());
  for (const auto& [engine, e] : plan.tol.ensemble) {
    if (!recorded.count(engine)) continue;
    for (const std::string& q : e.quantities) {
      const auto it = base.find(engine + "/" + q);
      const std::vector<double> b = it == base.end() ? std::vector<double>() : it->second;
      if (e.members > 0 ? b.size() != size_t(e.members) : b.size() < 2) {
        gates.fail(engine, q, mean_of(b), NAN,
                   "the baseline has " + std::to_string(b.size()) + " members, tolerances.toml " +
                       (e.members > 0 ? std::to_string(e.members) : std::string("2 or more")) +
                       " (record them with --update)");
        continue;
      }
      Gate g = ensemble_gate(plan.sc.name, engine, q, b, now.ensemble.at(engine + "/" + q), alpha);
      // what this gate can catch: the shift at the recorded spread and size
      const double d = detectable_shift(finite_spread(b), int(b.size()), alpha);
      if (!std::isnan(d))
        g.note += "; catches a shift of " + note_number(d) +
                  (e.detect.count(q) ? " (goal " + note_number(e.detect.at(q)) + ")" : "");
      gates.add(g);
    }
    const auto g = base.find(engine + "/growth_exponent");
    gates.ungated(engine, "growth_exponent", g == base.end() ? NAN : mean_of(g->second),
                  mean_of(now.ensemble.at(engine + "/growth_exponent")), NAN,
                  "for the record: ln(|dX(T)| / |dX(0)|) / T (1/s), members 0 and 1");
  }
}

/// Compares the run now with the recorded baseline, gate by gate.
std::vector<Gate> compare(const CheckPlan& plan, const CheckRun& now) {
  GateList gates(plan.sc.name);
  const Metrics base = read_metrics(plan.metrics_path());
  const Shapes shapes = read_shapes(plan.shape_path(), now.result.model);
  const std::set<std::string> recorded = compare_engines(base, shapes, now.result, gates);
  const bool ensembles_ran = !now.ensemble.empty();
  compare_metrics(base, recorded, plan.tol, now.result, ensembles_ran, gates);
  compare_shapes(shapes, recorded, plan.tol, now.result, ensembles_ran, gates);
  if (ensembles_ran) compare_ensembles(plan, now, recorded, gates);
  compare_stability(plan, now.brackets, gates);
  // the [test]'s metrics: recorded or measured on either side
  const fs::path tests_path = plan.dir / "tests.csv";
  const TestValues base_tests =
      fs::exists(tests_path) ? read_test_values(tests_path) : TestValues();
  for (const Gate& g : gate_test_metrics(plan.sc.name, base_tests, run_test_values(now.result),
                                         plan.tol, ensembles_ran))
    gates.add(g);
  return std::move(gates.gates());
}

}  // namespace

std::vector<Gate> check_scenario(const std::string& scenario_path, const CheckOptions& o) {
  const CheckPlan plan = plan_check(scenario_path, o);
  const CheckRun now = run_check(plan, o);
  return o.update ? record(plan, now, o) : compare(plan, now);
}

void PendingBaselines::commit() {
  for (const std::unique_ptr<CsvWriter>& f : m_files) f->commit();
  for (const std::string& path : m_removals) fs::remove(path);
  m_files.clear();
  m_removals.clear();
}

std::string format_gates(const std::vector<Gate>& gates) {
  std::ostringstream o;
  char line[512];
  std::snprintf(line, sizeof line, "%-18s %-32s %-22s %14s %14s %11s %11s  %s\n", "scenario",
                "engine", "quantity", "baseline", "now", "difference", "allowed", "verdict");
  o << line;
  for (const Gate& g : gates) {
    auto num = [](double v) { return cloth::significant(v, 6); };
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
