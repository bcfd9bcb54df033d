#include "harness/stability_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "cloth/linear_stability.hpp"
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

/// Halvings of the engine's own dt tried before a configuration is declared never stable:
/// each doubles the cost of a run, so ten already cost 2^11 runs at the engine's dt.
constexpr int kMaxHalvings = 10;

const std::vector<std::string> kHeader = {"engine",       "integrator",
                                          "stable_dt",    "first_unstable_dt",
                                          "predicted_dt", "ratio_measured_to_predicted",
                                          "cause",        "runs",
                                          "rerun",        "rerun_unstable"};

const char* kSidecar = "stability_scenario.toml";

std::string field(double v) {
  return std::isfinite(v) ? format_double(v) : std::string();
}

double number_or(const std::string& f, double otherwise) {
  return f.empty() ? otherwise : std::stod(f);
}

/// True when big is a whole multiple (>= 1) of small, up to round-off (as the loader checks).
bool whole_multiple(double big, double small) {
  const double r = big / small;
  const double n = std::round(r);
  return n >= 1 && std::abs(r - n) <= 1e-9 * r;
}

/// What stability_scenario.toml holds: the options that change a row, then the scenario.
std::string sidecar_text(const Scenario& sc, const StabilityOptions& o) {
  return "# the stability sweep whose rows stability.csv holds; --resume continues it only\n"
         "# with this scenario and these options:\n"
         "#   --dt-max " +
         format_double(o.dt_max) + " --rel-tol " + format_double(o.rel_tol) + "\n" +
         scenario_to_toml(sc);
}

/// Throws unless the folder's earlier sweep ran this scenario with these options.
void check_resumable(const std::string& dir, const Scenario& sc, const StabilityOptions& o) {
  const std::string csv = dir + "stability.csv", sidecar = dir + kSidecar;
  const std::string earlier = read_text(sidecar);
  const std::string now = sidecar_text(sc, o);
  if (earlier.empty()) {
    if (!read_text(csv).empty())
      throw std::runtime_error(csv + ": cannot resume: there is no " + kSidecar +
                               " beside it to say which scenario and options its rows come "
                               "from; run without --resume or choose another output folder");
    return;
  }
  if (earlier == now) return;
  // say which part differs: the comment lines hold the options, the rest the scenario
  const auto split = [](const std::string& text) {
    size_t at = 0;
    while (at < text.size() && text[at] == '#') {
      const size_t end = text.find('\n', at);
      at = end == std::string::npos ? text.size() : end + 1;
    }
    const size_t from = text.find("--dt-max");
    const std::string options = from < at ? text.substr(from, text.find('\n', from) - from)
                                          : std::string("(none recorded)");
    return std::make_pair(options, text.substr(at));
  };
  const auto [earlier_options, earlier_scenario] = split(earlier);
  const auto [options, scenario] = split(now);
  const std::string what =
      earlier_scenario != scenario
          ? "another scenario (or other --set overrides or --engine choices)"
          : "other options (" + earlier_options + " then, " + options + " now)";
  throw std::runtime_error(sidecar + ": cannot resume: the folder holds a stability sweep of " +
                           what + "; run without --resume or choose another output folder");
}

}  // namespace

double stability_horizon(const Scenario& sc) {
  // run_engine logs llround(duration / frame_interval) frames
  const long long frames = std::max(1LL, std::llround(sc.duration / sc.frame_interval));
  const double whole = double(frames) * sc.frame_interval;
  return std::abs(whole - sc.duration) <= 1e-9 * sc.duration ? sc.duration : whole;
}

std::string stability_rerun(const Scenario& sc, const EngineSpec& e) {
  const double horizon = stability_horizon(sc);
  std::string s = rerun_overrides(e) + " --set frame_interval=" + format_double(horizon);
  if (horizon != sc.duration) s += " --set duration=" + format_double(horizon);
  if (sc.snapshot_interval > 0 && !whole_multiple(sc.snapshot_interval, horizon))
    s += " --set snapshot_interval=0";
  return s;
}

bool stable_run(const Scenario& sc, const EngineSpec& e, std::string* cause) {
  // one frame over the horizon: the blow-up check runs every step regardless
  Scenario s = sc;
  s.duration = s.frame_interval = stability_horizon(sc);
  s.snapshot_interval = 0;
  const cloth::Model model = cloth::build_model(s.scene);
  const EngineRun run = run_engine(s, e, model, nullptr, false);
  if (!run.stable && cause)
    *cause = std::isfinite(run.frames.back().max_strain) ? "strain" : "non-finite";
  return run.stable;
}

std::vector<StabilityRow> run_stability(const Scenario& sc, const StabilityOptions& o) {
  if (o.out_dir.empty()) throw std::invalid_argument("stability: no output folder given");
  if (!(o.dt_max > 0)) throw std::invalid_argument("--dt-max: expected a time step > 0");
  if (!(o.rel_tol > 0)) throw std::invalid_argument("--rel-tol: expected a number > 0");
  // the configurations: engine x integrator
  struct Config {
    EngineSpec engine;
    std::string integrator;
  };
  std::vector<Config> configs;
  for (const EngineSpec& e : sc.engines) {
    if (!o.engines.empty() &&
        std::find(o.engines.begin(), o.engines.end(), e.name) == o.engines.end())
      continue;
    if (e.kind != EngineKind::custom) {
      configs.push_back({e, ""});
      continue;
    }
    for (cloth::Integrator i : cloth::all_integrators()) {
      const std::string name = cloth::integrator_name(i);
      if (o.integrators.empty() ||
          std::find(o.integrators.begin(), o.integrators.end(), name) != o.integrators.end())
        configs.push_back({with_integrator_and_dt(e, name, e.dt), name});
    }
  }
  for (const std::string& name : o.engines)
    if (std::none_of(sc.engines.begin(), sc.engines.end(),
                     [&](const EngineSpec& e) { return e.name == name; }))
      throw std::invalid_argument("--engine " + name + ": no such engine in " + sc.source);
  for (const std::string& name : o.integrators)
    if (!cloth::parse_integrator(name))
      throw std::invalid_argument("--integrator " + name + ": unknown integrator");
  if (configs.empty()) throw std::invalid_argument("nothing to sweep: no engine matches");
  for (const Config& c : configs) require_engine_can_model(c.engine, sc.scene, "");

  // the folder: an earlier sweep is only resumed when it ran the same scenario and options
  make_directories(o.out_dir);
  const std::string dir = o.out_dir + "/";
  if (o.resume) check_resumable(dir, sc, o);
  {
    AtomicFile f(dir + kSidecar);
    f.write(sidecar_text(sc, o));
    f.commit();
  }
  SweepTable table(dir + "stability.csv", kHeader, 2, o.resume);

  // the step grid: horizon / n for whole n, no larger than dt_max
  const double horizon = stability_horizon(sc);
  const long long n_min =
      std::max(1LL, static_cast<long long>(std::ceil(horizon / o.dt_max * (1 - 1e-12))));
  const auto dt_of = [&](long long n) { return horizon / double(n); };

  const cloth::LinearSpectrum spectrum = cloth::linear_spectrum(cloth::build_model(sc.scene));
  Progress progress(double(configs.size()), "searches", o.progress);
  std::vector<StabilityRow> rows(configs.size());
  std::vector<std::string> order;
  for (const Config& c : configs) order.push_back(c.engine.name + "," + c.integrator);

  run_parallel(static_cast<int>(configs.size()), o.jobs, [&](int index) {
    const Config& c = configs[static_cast<size_t>(index)];
    StabilityRow row;
    row.engine = c.engine.name;
    row.integrator = c.integrator;
    const std::string key = row.engine + "," + row.integrator;
    if (table.done(key)) {
      const auto f = table.row(key);
      row.stable_dt = number_or(f[2], kNaN);
      row.first_unstable_dt = number_or(f[3], kInf);
      row.predicted_dt = number_or(f[4], kNaN);
      row.ratio = number_or(f[5], kNaN);
      row.cause = f[6];
      row.runs = std::stoi(f[7]);
      row.rerun = f[8];
      row.rerun_unstable = f[9];
      row.resumed = true;
      rows[static_cast<size_t>(index)] = row;
      progress.advance(1, key + " (resumed)");
      return;
    }
    std::string cause;
    const auto spec = [&](long long n) {
      return with_integrator_and_dt(c.engine, c.integrator, dt_of(n));
    };
    const auto stable = [&](long long n) {
      ++row.runs;
      if (interrupt_requested()) throw Interrupted();
      return stable_run(sc, spec(n), &cause);
    };
    // bracket on the step grid: n_stable steps stable, n_unstable (< n_stable) unstable;
    // 0 where none was found
    long long n_stable = 0, n_unstable = 0;
    std::string unstable_cause;
    const long long n_engine = std::max(1LL, std::llround(horizon / c.engine.dt));
    const long long n0 = std::max(n_min, n_engine);
    if (stable(n0)) {
      // double dt (halve n) until a run fails or dt_max is reached
      n_stable = n0;
      while (n_stable > n_min) {
        const long long next = std::max(n_min, (n_stable + 1) / 2);
        if (!stable(next)) {
          n_unstable = next;
          unstable_cause = cause;
          break;
        }
        n_stable = next;
      }
    } else {
      n_unstable = n0;
      unstable_cause = cause;
      for (int k = 0; k < kMaxHalvings; ++k) {
        if (stable(2 * n_unstable)) {
          n_stable = 2 * n_unstable;
          break;
        }
        n_unstable *= 2;
        unstable_cause = cause;
      }
    }
    // bisect on a log scale, down to neighbours on the grid
    while (n_stable > 0 && n_unstable > 0 && n_stable - n_unstable > 1 &&
           double(n_stable) / double(n_unstable) - 1.0 > o.rel_tol) {
      const long long mid =
          std::clamp<long long>(std::llround(std::sqrt(double(n_stable) * double(n_unstable))),
                                n_unstable + 1, n_stable - 1);
      if (stable(mid)) {
        n_stable = mid;
      } else {
        n_unstable = mid;
        unstable_cause = cause;
      }
    }
    if (n_stable > 0) row.stable_dt = dt_of(n_stable);
    if (n_unstable > 0) row.first_unstable_dt = dt_of(n_unstable);
    if (n_stable > 0) row.rerun = stability_rerun(sc, spec(n_stable));
    if (n_unstable > 0) row.rerun_unstable = stability_rerun(sc, spec(n_unstable));

    // the cause: what failed, or why nothing did
    std::string limiting;
    if (c.engine.kind == EngineKind::custom) {
      row.predicted_dt = cloth::predicted_stable_dt(c.engine.solver.integrator, spectrum);
      limiting = "limiting mode " +
                 cloth::limiting_mode(c.engine.solver.integrator, spectrum, row.predicted_dt);
    }
    if (n_stable == 0) {
      row.cause = unstable_cause + " at every dt tried down to " +
                  format_double(row.first_unstable_dt) + " s (the engine's dt / 2^" +
                  std::to_string(kMaxHalvings) + "): no stable dt found";
    } else if (n_unstable == 0) {
      row.cause = "no failure up to --dt-max = " + format_double(o.dt_max) +
                  " s: stable_dt is a lower bound of the limit";
    } else {
      row.cause = unstable_cause;
    }
    if (!limiting.empty()) row.cause += "; " + limiting;
    if (n_engine < n_min)
      row.cause += "; the engine's dt " + format_double(c.engine.dt) +
                   " s is above --dt-max: the search started at " + format_double(dt_of(n0)) + " s";
    if (c.engine.kind == EngineKind::custom && !spectrum.exact) row.cause += " (" + spectrum.method + ")";
    // a ratio only between two limits: a bound or a missing measurement gives none
    if (n_stable > 0 && n_unstable > 0 && std::isfinite(row.predicted_dt))
      row.ratio = row.stable_dt / row.predicted_dt;

    table.append({row.engine, row.integrator, field(row.stable_dt), field(row.first_unstable_dt),
                  field(row.predicted_dt), field(row.ratio), row.cause, std::to_string(row.runs),
                  row.rerun, row.rerun_unstable});
    rows[static_cast<size_t>(index)] = row;
    progress.advance(1, key);
  });
  table.finish(order);
  return rows;
}

}  // namespace clothbench
