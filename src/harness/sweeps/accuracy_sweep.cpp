#include "harness/sweeps/accuracy_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "cloth/model/constants.hpp"
#include "cloth/model/model.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/text_file.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/progress.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_writer.hpp"
#include "harness/sweeps/accuracy_files.hpp"
#include "harness/sweeps/accuracy_plan.hpp"
#include "harness/sweeps/sweep.hpp"
#include "harness/sweeps/sweep_table.hpp"

namespace clothbench {

namespace {

/// A sweep's scenario.toml without its budget line (budget_line), if it has one.
std::string without_budget(const std::string& toml) {
  const std::string mark = "# --max-run-seconds ";
  if (toml.rfind(mark, 0) != 0) return toml;
  const size_t end = toml.find('\n');
  return end == std::string::npos ? "" : toml.substr(end + 1);
}

using cloth::kInf;
using cloth::kNaN;

double rms_distance(const cloth::Matrix3X& a, const cloth::Matrix3X& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The scenes a sweep runs on and their models: the scenario's own, then each grid's.
struct Scenes {
  const Scenario& sc;
  const AccuracyPlan& plan;
  cloth::Model model;
  std::vector<cloth::Model> grid_models;

  Scenes(const Scenario& s, const AccuracyPlan& p)
      : sc(s), plan(p), model(cloth::build_model(s.scene)) {
    for (const Scenario& g : p.grids) grid_models.push_back(cloth::build_model(g.scene));
  }
  const Scenario& scenario(int grid) const { return grid < 0 ? sc : plan.grids[size_t(grid)]; }
  const cloth::Model& model_of(int grid) const {
    return grid < 0 ? model : grid_models[size_t(grid)];
  }
};

/// A shard's share of the time-step study (plan.configs and dt_keys reduced to the rows it
/// owns), and the record of the whole study for shard.toml (plan_accuracy refuses a shard of a
/// sweep with a resolution study).
ShardPlan take_shard(AccuracyPlan& plan, const Shard& shard) {
  ShardPlan whole = {"accuracy", "work_precision.csv", {"scenario.toml", "reference.csv"}, 3,
                     3,          plan.dt_keys};
  if (!shard.sharded()) return whole;
  std::vector<AccuracyConfig> configs;
  plan.dt_keys.clear();
  for (size_t i = 0; i < plan.configs.size(); ++i)
    if (shard.owns(i)) {
      configs.push_back(plan.configs[i]);
      plan.dt_keys.push_back(plan.configs[i].key);
    }
  plan.configs = configs;
  return whole;
}

/// The folder holds this sweep alone: an earlier one is only resumed when it ran the same
/// scenario and references (its error floor is then kept); files of an earlier sweep that
/// this one would not rewrite go. Writes scenario.toml and reference.csv.
void prepare_folder(const Scenario& sc, const AccuracyOptions& o, AccuracyPlan& plan,
                    const ShardPlan& shard_plan) {
  make_directories(o.out_dir);
  const std::string dir = o.out_dir + "/";
  record_shard(dir, o.shard, shard_plan, o.resume);
  const std::string toml = budget_line(sc) + scenario_to_toml(sc);
  if (o.resume) {
    const std::map<std::string, CsvRecord> earlier_refs = read_references(dir + "reference.csv");
    const std::string earlier = read_text(dir + "scenario.toml");
    if (!earlier.empty() && earlier != toml)
      throw UserError(dir + "scenario.toml: cannot resume: the folder holds a sweep of " +
                      (without_budget(earlier) == scenario_to_toml(sc)
                           ? "another --max-run-seconds"
                           : "another scenario (or other --set overrides)") +
                      "; run without --resume or choose another output folder");
    check_resumable_reference(dir + "reference.csv", earlier_refs, plan.reference);
    if (!plan.grids.empty())
      check_resumable_reference(dir + "reference.csv", earlier_refs, plan.resolution_reference);
    auto it = earlier_refs.find("dt");
    if (it != earlier_refs.end()) plan.reference.error_floor = it->second.number(5, kNaN);
  }
  // what the report derives from the rows goes until the report writes it again, so that
  // a sweep that stops early never leaves an older sweep's fits beside its rows
  std::vector<std::string> stale = {"convergence.csv", "recommendation.csv",
                                    "resolution_recommendation.csv"};
  if (plan.grids.empty())
    stale.insert(stale.end(), {"resolution.csv", "resolution_recommendation.csv"});
  for (const std::string& f : stale) std::filesystem::remove(dir + f);
  AtomicFile f(dir + "scenario.toml");
  f.write(toml);
  f.commit();
  write_run_info(dir);
}

/// Rewrites reference.csv with the references as they stand.
void write_reference_file(const std::string& dir, const AccuracyPlan& plan) {
  std::vector<AccuracyReference> refs = {plan.reference};
  std::vector<std::string> reruns = {plan.reference_run.rerun};
  if (!plan.grids.empty()) {
    refs.push_back(plan.resolution_reference);
    reruns.push_back(plan.resolution_reference_run.rerun);
  }
  write_references(dir + "reference.csv", refs, reruns);
}

/// The rows of both studies, typed, as they are kept from an earlier sweep or finish now;
/// each is also appended to its table file at once (thread-safe).
class AccuracyRows {
 public:
  AccuracyRows(const std::string& dir, const AccuracyPlan& plan, bool resume)
      : m_particles(plan.reference.nu * plan.reference.nv),
        m_dt_table(dir + "work_precision.csv", work_precision_header(), 3, resume) {
    if (!plan.grids.empty())
      m_res_table =
          std::make_unique<SweepTable>(dir + "resolution.csv", resolution_header(), 3, resume);
  }

  /// Takes the configuration's row from the earlier sweep; false when it has none.
  bool resume(const AccuracyConfig& c) {
    const CsvRecord* kept = table(c).kept(c.key);
    if (!kept) return false;
    rows(c)[c.key] = c.grid < 0 ? work_precision_row(*kept, m_particles) : resolution_row(*kept);
    return true;
  }

  /// Records a row that finished now and appends it to its file.
  void add(const AccuracyConfig& c, const AccuracyRow& row) {
    table(c).append(c.grid < 0 ? work_precision_fields(row) : resolution_fields(row));
    std::lock_guard<std::mutex> lock(m_mutex);
    rows(c)[c.key] = row;
  }

  /// Rewrites both tables in their fixed order; returns the rows of the time-step study and
  /// (when there is one) of the resolution study, in that order.
  std::pair<std::vector<AccuracyRow>, std::vector<AccuracyRow>> finish(const AccuracyPlan& plan) {
    m_dt_table.finish(plan.dt_keys);
    std::vector<AccuracyRow> res;
    if (m_res_table) {
      m_res_table->finish(plan.res_keys);
      res = in_order(m_res_rows, plan.res_keys);
    }
    return {in_order(m_dt_rows, plan.dt_keys), res};
  }

 private:
  SweepTable& table(const AccuracyConfig& c) { return c.grid < 0 ? m_dt_table : *m_res_table; }
  std::map<std::string, AccuracyRow>& rows(const AccuracyConfig& c) {
    return c.grid < 0 ? m_dt_rows : m_res_rows;
  }
  static std::vector<AccuracyRow> in_order(const std::map<std::string, AccuracyRow>& rows,
                                           const std::vector<std::string>& keys) {
    std::vector<AccuracyRow> out;
    for (const std::string& k : keys) {
      auto it = rows.find(k);
      if (it == rows.end()) throw std::logic_error("accuracy: no row " + k + " after the sweep");
      out.push_back(it->second);
    }
    return out;
  }

  int m_particles;
  SweepTable m_dt_table;
  std::unique_ptr<SweepTable> m_res_table;
  std::map<std::string, AccuracyRow> m_dt_rows, m_res_rows;
  std::mutex m_mutex;
};

/// Two configurations that differ in engine name only run the same computation: the resolved
/// TOML of the engine alone, its name blanked, says whether they do.
std::string signature(const EngineSpec& e, int grid) {
  Scenario s;
  s.engines = {e};
  s.engines[0].name = "";
  return std::to_string(grid) + "\n" + scenario_to_toml(s);
}

/// The configurations still to run, grouped so that identical ones run once (indices into
/// plan.configs); the others are taken from the earlier sweep and counted in resumed.
std::vector<std::vector<size_t>> missing_groups(const AccuracyPlan& plan, AccuracyRows& rows,
                                                int* resumed) {
  std::vector<std::vector<size_t>> groups;
  std::map<std::string, size_t> group_of;
  for (size_t i = 0; i < plan.configs.size(); ++i) {
    const AccuracyConfig& c = plan.configs[i];
    if (rows.resume(c)) {
      ++*resumed;
      continue;
    }
    const std::string sig = signature(c.spec, c.grid);
    auto it = group_of.find(sig);
    if (it == group_of.end()) {
      group_of[sig] = groups.size();
      groups.push_back({i});
    } else {
      groups[it->second].push_back(i);
    }
  }
  return groups;
}

}  // namespace

namespace {

/// A reference run to make before the configurations (every error needs it).
struct RefJob {
  int grid;  // -1: the scenario's own grid
  EngineSpec spec;
  bool keep_positions;
  EngineRun run;
};

/// The reference runs a sweep still needs: the time-step reference when a row of its study
/// is missing or its error floor is unknown, rk4 at twice its dt for that floor, and the
/// resolution reference when a row of its study is missing.
struct ReferenceJobs {
  std::vector<RefJob> jobs;
  int dt = -1, floor = -1, resolution = -1;  // indices into jobs; -1: not run

  const EngineRun* run(int index) const { return index >= 0 ? &jobs[size_t(index)].run : nullptr; }
};

ReferenceJobs plan_reference_jobs(const AccuracyPlan& plan,
                                  const std::vector<std::vector<size_t>>& groups) {
  bool dt_missing = false, res_missing = false;
  for (const auto& g : groups) (plan.configs[g.front()].grid < 0 ? dt_missing : res_missing) = true;
  ReferenceJobs r;
  const bool no_floor = std::isnan(plan.reference.error_floor);
  if (dt_missing || no_floor) {
    r.dt = static_cast<int>(r.jobs.size());
    r.jobs.push_back({-1, plan.reference_run.spec, true, {}});
  }
  if (no_floor) {
    r.floor = static_cast<int>(r.jobs.size());
    r.jobs.push_back({-1, plan.floor_run.spec, false, {}});
  }
  if (res_missing) {
    r.resolution = static_cast<int>(r.jobs.size());
    r.jobs.push_back({int(plan.grids.size()) - 1, plan.resolution_reference_run.spec, false, {}});
  }
  return r;
}

/// Steps the whole sweep will take: the references once, each group's repeats.
double planned_total_steps(const Scenes& scenes, const ReferenceJobs& refs,
                           const std::vector<std::vector<size_t>>& groups, int repeats) {
  double total = 0;
  for (const RefJob& j : refs.jobs) total += double(planned_steps(scenes.scenario(j.grid), j.spec));
  for (const auto& g : groups) {
    const AccuracyConfig& c = scenes.plan.configs[g.front()];
    total += double(repeats) * double(planned_steps(scenes.scenario(c.grid), c.spec));
  }
  return total;
}

std::string grid_name(int nu, int nv) {
  return std::to_string(nu) + " x " + std::to_string(nv);
}

/// Runs the references; throws UserError when one blows up.
void run_references(const Scenes& scenes, ReferenceJobs& refs, int jobs, Progress& progress) {
  // run_engine draws the bar from its own thread: only one reference job may hold it, the
  // others count their steps once all are done
  const int ref_threads = std::min(jobs, static_cast<int>(refs.jobs.size()));
  run_parallel(static_cast<int>(refs.jobs.size()), jobs, [&](int i) {
    RefJob& j = refs.jobs[static_cast<size_t>(i)];
    Progress* live = i == 0 || ref_threads == 1 ? &progress : nullptr;
    j.run = run_engine(scenes.scenario(j.grid), j.spec, scenes.model_of(j.grid), live,
                       j.keep_positions);
  });
  if (ref_threads > 1)
    for (size_t i = 1; i < refs.jobs.size(); ++i)
      progress.advance(double(planned_steps(scenes.scenario(refs.jobs[i].grid), refs.jobs[i].spec)),
                       "references");
  for (const RefJob& j : refs.jobs) {
    if (j.run.stable) continue;
    const Scenario& s = scenes.scenario(j.grid);
    const std::string what = "the reference (rk4 at dt = " + format_double(j.spec.dt) + " s on " +
                             grid_name(s.scene.cloth.nu, s.scene.cloth.nv) + " particles)";
    if (j.run.timed_out)
      throw UserError(what + " did not finish within --max-run-seconds " +
                      format_double(s.max_run_seconds) +
                      " s; allow it more time or sweep larger time steps (--dts)");
    throw UserError(what + " blew up at t = " + format_double(j.run.blowup_t) + " s: " +
                    scenes.sc.source + " is not stable even so; sweep smaller time steps (--dts)");
  }
}

/// The reference's error floor: rk4 at twice its dt against it.
double error_floor(const ReferenceJobs& refs) {
  return rms_distance(refs.run(refs.floor)->snapshots.back(), refs.run(refs.dt)->snapshots.back());
}

/// A run of one configuration, its wall time the median over repeats.
struct TimedRun {
  EngineRun run;
  double wall_s = 0;  // s
};

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

/// The row of configuration c from its run: the error against its study's reference
/// (time-step study: RMS distance at every logged frame; resolution study: at common
/// material points of the final shapes) and the cost.
AccuracyRow measure(const AccuracyPlan& plan, const AccuracyConfig& c, const TimedRun& t,
                    const ReferenceJobs& refs) {
  const EngineRun& run = t.run;
  const double simulated_s = double(run.counters.steps) * run.spec.dt;
  AccuracyRow row;
  row.engine = c.spec.name;
  row.integrator = integrator_label(c.integrator);
  row.dt = c.spec.dt;
  row.stable = run.stable;
  row.wall_s_per_sim_s = simulated_s > 0 ? t.wall_s / simulated_s : 0.0;
  row.force_evals = run.counters.force_evals;
  row.cg_iterations = run.counters.cg_iterations;
  row.rerun = c.rerun;
  if (c.grid < 0) {
    const EngineRun& ref = *refs.run(refs.dt);
    row.particles = plan.reference.nu * plan.reference.nv;
    row.wall_s = t.wall_s;
    // both runs log the same frame times
    if (run.stable && run.positions.size() != ref.positions.size())
      throw std::logic_error("accuracy: frame counts differ from the reference's");
    if (run.stable) row.error_max = 0;
    for (size_t k = 0; run.stable && k < run.positions.size(); ++k) {
      row.error_final = rms_distance(run.positions[k], ref.positions[k]);
      // a NaN sticks (std::max would drop it)
      if (!std::isnan(row.error_max) && !(row.error_final <= row.error_max))
        row.error_max = row.error_final;
    }
  } else {
    const int n = plan.sizes[size_t(c.grid)], nr = plan.sizes.back();
    row.particles = n * n;
    row.error_max = kNaN;
    if (run.stable)
      row.error_final = material_rms_distance(run.snapshots.back(), n, n,
                                              refs.run(refs.resolution)->snapshots.back(), nr, nr);
  }
  // as written and read back: a missing error is infinite
  if (!std::isfinite(row.error_final)) row.error_final = kInf;
  if (c.grid < 0 && !std::isfinite(row.error_max)) row.error_max = kInf;
  return row;
}

/// Runs every group's configuration once and records one row per member.
void run_configs(const Scenes& scenes, const std::vector<std::vector<size_t>>& groups,
                 const ReferenceJobs& refs, const AccuracyOptions& o, AccuracyRows& rows,
                 Progress& progress, int* runs) {
  std::mutex progress_mutex;
  const AccuracyPlan& plan = scenes.plan;
  run_parallel(static_cast<int>(groups.size()), std::max(1, o.jobs), [&](int gi) {
    const std::vector<size_t>& members = groups[size_t(gi)];
    const AccuracyConfig& first = plan.configs[members.front()];
    const Scenario& s = scenes.scenario(first.grid);
    const TimedRun t =
        timed_run(s, scenes.model_of(first.grid), first.spec, o.repeats, first.grid < 0);
    for (size_t i : members) rows.add(plan.configs[i], measure(plan, plan.configs[i], t, refs));
    std::lock_guard<std::mutex> lock(progress_mutex);
    *runs += 1;
    progress.advance(
        double(o.repeats) * double(planned_steps(s, first.spec)),
        first.spec.name + (first.integrator ? " " + integrator_label(first.integrator) : ""));
  });
}

/// The fitted orders and the recommendations from the rows, and the files that hold them.
void report(const AccuracyPlan& plan, const AccuracyOptions& o, AccuracyReport& report) {
  const std::string dir = o.out_dir + "/";
  report.convergence = fit_convergence(report.rows, report.reference.error_floor);
  write_convergence(dir + "convergence.csv", report.convergence);
  report.files.push_back(dir + "convergence.csv");
  if (!(o.tolerance > 0)) return;
  // the cheapest configuration within the tolerance, per engine and overall
  report.recommendations =
      recommend_all(report.rows, plan.engine_names, o.tolerance, &AccuracyRow::error_max);
  write_recommendations(dir + "recommendation.csv", report.recommendations, o.tolerance);
  report.files.push_back(dir + "recommendation.csv");
  if (plan.grids.empty()) return;
  report.resolution_recommendations = recommend_all(report.resolution_rows, plan.engine_names,
                                                    o.tolerance, &AccuracyRow::error_final);
  write_resolution_recommendations(dir + "resolution_recommendation.csv",
                                   report.resolution_recommendations, o.tolerance);
  report.files.push_back(dir + "resolution_recommendation.csv");
}

/// The files a sweep writes into its folder.
const std::vector<std::string> kAccuracyFiles = {
    "scenario.toml",  "run.json",        "reference.csv",      "work_precision.csv",
    "resolution.csv", "convergence.csv", "recommendation.csv", "resolution_recommendation.csv",
    kShardFile};

AccuracyReport sweep(const Scenario& sc, const AccuracyOptions& o) {
  // plan: every configuration and reference, and the folder they go in
  AccuracyPlan plan = plan_accuracy(sc, o);
  const ShardPlan shard_plan = take_shard(plan, o.shard);
  const std::string dir = o.out_dir + "/";
  prepare_folder(sc, o, plan, shard_plan);
  write_reference_file(dir, plan);
  AccuracyRows rows(dir, plan, o.resume);
  AccuracyReport result;
  result.tolerance = o.tolerance;
  const std::vector<std::vector<size_t>> groups = missing_groups(plan, rows, &result.resumed);

  // run: the references first, then every missing row
  const Scenes scenes(sc, plan);
  ReferenceJobs refs = plan_reference_jobs(plan, groups);
  Progress progress(planned_total_steps(scenes, refs, groups, o.repeats), "steps", o.progress);
  if (refs.dt >= 0) progress.line("reference: " + plan.reference.description);
  if (refs.resolution >= 0)
    progress.line("resolution reference: " + plan.resolution_reference.description);
  run_references(scenes, refs, std::max(1, o.jobs), progress);
  if (refs.floor >= 0) {
    plan.reference.error_floor = error_floor(refs);
    write_reference_file(dir, plan);
  }
  run_configs(scenes, groups, refs, o, rows, progress, &result.runs);

  // report: the tables in their fixed order, the fits and the recommendations
  result.reference = plan.reference;
  result.resolution_reference = plan.resolution_reference;
  std::tie(result.rows, result.resolution_rows) = rows.finish(plan);
  result.files = {dir + "scenario.toml", dir + "reference.csv", dir + "work_precision.csv"};
  if (!plan.grids.empty()) result.files.push_back(dir + "resolution.csv");
  if (!o.shard.sharded()) report(plan, o, result);  // a shard's rows are not the whole study
  return result;
}

}  // namespace

AccuracyReport run_accuracy(const Scenario& sc, const AccuracyOptions& o) {
  std::vector<std::string> created;  // files of the sweep not in the folder before it
  for (const std::string& f : kAccuracyFiles)
    if (!std::filesystem::exists(o.out_dir + "/" + f)) created.push_back(o.out_dir + "/" + f);
  try {
    return sweep(sc, o);
  } catch (const UserError&) {
    // a sweep refused (bad options, a reference that blows up) leaves nothing it created;
    // an interrupted one keeps its rows for --resume
    std::error_code ec;
    for (const std::string& f : created) std::filesystem::remove(f, ec);
    throw;
  }
}

}  // namespace clothbench
