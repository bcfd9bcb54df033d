#include "harness/stability_sweep.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "cloth/linear_stability.hpp"
#include "harness/csv_writer.hpp"
#include "harness/engine_factory.hpp"
#include "harness/progress.hpp"
#include "harness/runner.hpp"

namespace clothbench {

namespace {

const std::vector<std::string> kHeader = {"engine",       "integrator",
                                          "stable_dt",    "first_unstable_dt",
                                          "predicted_dt", "ratio_measured_to_predicted",
                                          "cause",        "runs",
                                          "rerun"};

std::string field(double v) {
  return std::isnan(v) ? std::string() : format_double(v);
}

}  // namespace

bool stable_run(const Scenario& sc, const EngineSpec& e, std::string* cause) {
  // one frame at the end: the blow-up check runs every step regardless
  Scenario s = sc;
  s.frame_interval = s.duration;
  s.snapshot_interval = 0;
  const cloth::Model model = cloth::build_model(s.scene);
  const EngineRun run = run_engine(s, e, model, nullptr, false);
  if (!run.stable && cause)
    *cause = std::isfinite(run.frames.back().max_strain) ? "strain" : "non-finite";
  return run.stable;
}

std::vector<StabilityRow> run_stability(const Scenario& sc, const StabilityOptions& o) {
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
    if (e.kind != "custom") {
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
  for (const Config& c : configs) make_engine(c.engine, sc.scene);  // refuse bad scenes early

  make_directories(o.out_dir);
  SweepTable table(o.out_dir + "/stability.csv", kHeader, 2, o.resume);
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
      row.stable_dt = std::stod(f[2]);
      row.first_unstable_dt =
          f[3].empty() ? std::numeric_limits<double>::infinity() : std::stod(f[3]);
      row.predicted_dt = f[4].empty() ? NAN : std::stod(f[4]);
      row.cause = f[6];
      row.runs = std::stoi(f[7]);
      row.rerun = f[8];
      rows[static_cast<size_t>(index)] = row;
      progress.advance(1, key + " (resumed)");
      return;
    }
    std::string cause;
    auto stable = [&](double dt) {
      ++row.runs;
      if (interrupt_requested()) throw Interrupted();
      return stable_run(sc, with_integrator_and_dt(c.engine, c.integrator, dt), &cause);
    };
    // bracket: [lo stable, hi unstable]
    double lo = c.engine.dt, hi = std::numeric_limits<double>::infinity();
    std::string hi_cause;
    if (!stable(lo)) {
      hi = lo;
      hi_cause = cause;
      for (int k = 0; k < 20 && !stable(lo /= 2); ++k) {
        hi = lo;
        hi_cause = cause;
      }
    } else {
      while (lo < o.dt_max) {
        const double next = std::min(2 * lo, o.dt_max);
        if (!stable(next)) {
          hi = next;
          hi_cause = cause;
          break;
        }
        lo = next;
      }
    }
    // bisect on a log scale
    while (std::isfinite(hi) && hi / lo - 1.0 > o.rel_tol) {
      const double mid = std::sqrt(lo * hi);
      if (stable(mid)) {
        lo = mid;
      } else {
        hi = mid;
        hi_cause = cause;
      }
    }
    row.stable_dt = lo;
    row.first_unstable_dt = hi;
    if (c.engine.kind == "custom") {
      const double p = cloth::predicted_stable_dt(c.engine.solver.integrator, spectrum);
      row.predicted_dt = p;
      const std::string mode = cloth::limiting_mode(c.engine.solver.integrator, spectrum);
      row.cause = std::isfinite(hi) ? hi_cause + "; limiting mode " + mode : "stable up to dt_max";
      if (!spectrum.exact)
        row.cause += " (damping not proportional to stiffness: modal damping approximated)";
    } else {
      row.predicted_dt = NAN;
      row.cause = std::isfinite(hi) ? hi_cause : "stable up to dt_max";
    }
    row.rerun = rerun_overrides(with_integrator_and_dt(c.engine, c.integrator, lo));
    const double ratio = std::isfinite(row.predicted_dt) ? row.stable_dt / row.predicted_dt : NAN;
    table.append({row.engine, row.integrator, format_double(row.stable_dt),
                  std::isfinite(hi) ? format_double(hi) : std::string(), field(row.predicted_dt),
                  std::isfinite(ratio) ? format_double(ratio) : std::string(), row.cause,
                  std::to_string(row.runs), row.rerun});
    rows[static_cast<size_t>(index)] = row;
    progress.advance(1, key);
  });
  table.finish(order);
  return rows;
}

}  // namespace clothbench
