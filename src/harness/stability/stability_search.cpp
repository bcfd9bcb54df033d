#include "harness/stability/stability_search.hpp"

#include <algorithm>
#include <cmath>

#include "cloth/model/model.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario_format.hpp"
#include "harness/sweeps/sweep.hpp"

namespace clothbench {

namespace {

/// One search: the runs it makes and the bracket it narrows.
class Search {
 public:
  Search(const Scenario& sc, const EngineSpec& engine, std::optional<cloth::Integrator> integrator)
      : m_sc(sc), m_engine(engine), m_integrator(integrator), m_horizon(stability_horizon(sc)) {}

  /// Whether the run of n steps is stable (counted; cause() says how it failed).
  bool stable(long long n) {
    ++m_bracket.runs;
    if (interrupt_requested()) throw Interrupted();
    return stable_run(m_sc, with_integrator_and_dt(m_engine, m_integrator, m_horizon / double(n)),
                      &m_cause, &m_bracket.steps);
  }

  /// From n0: double dt (halve n) until a run fails or n_min is reached.
  void grow(long long n0, long long n_min) {
    StabilityBracket& b = m_bracket;
    b.n_stable = n0;
    while (b.n_stable > n_min) {
      const long long next = std::max(n_min, (b.n_stable + 1) / 2);
      if (!stable(next)) {
        unstable(next);
        return;
      }
      b.n_stable = next;
    }
  }

  /// From an unstable n0: halve dt (double n) until a run holds, kMaxHalvings times at most.
  void shrink(long long n0) {
    StabilityBracket& b = m_bracket;
    unstable(n0);
    // a smaller dt only takes longer: after a timeout the search ends with no stable dt, and
    // no run of more than kMaxSteps steps is made
    for (int k = 0;
         k < kMaxHalvings && m_cause != "timeout" && double(2 * m_bracket.n_unstable) <= kMaxSteps;
         ++k) {
      if (stable(2 * b.n_unstable)) {
        b.n_stable = 2 * b.n_unstable;
        return;
      }
      unstable(2 * b.n_unstable);
    }
  }

  /// Bisects on a log scale, down to neighbours on the grid or within rel_tol.
  void bisect(double rel_tol) {
    StabilityBracket& b = m_bracket;
    while (b.n_stable > 0 && b.n_unstable > 0 && b.n_stable - b.n_unstable > 1 &&
           double(b.n_stable) / double(b.n_unstable) - 1.0 > rel_tol) {
      const long long mid =
          std::clamp<long long>(std::llround(std::sqrt(double(b.n_stable) * double(b.n_unstable))),
                                b.n_unstable + 1, b.n_stable - 1);
      if (stable(mid))
        b.n_stable = mid;
      else
        unstable(mid);
    }
  }

  StabilityBracket& bracket() { return m_bracket; }

 private:
  void unstable(long long n) {
    m_bracket.n_unstable = n;
    m_bracket.unstable_cause = m_cause;
  }

  const Scenario& m_sc;
  const EngineSpec& m_engine;
  std::optional<cloth::Integrator> m_integrator;
  double m_horizon;
  std::string m_cause;
  StabilityBracket m_bracket;
};

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
  if (sc.animation_interval > 0 && !whole_multiple(sc.animation_interval, horizon))
    s += " --set animation_interval=0";
  return s;
}

bool stable_run(const Scenario& sc, const EngineSpec& e, std::string* cause, long long* steps) {
  // one frame over the horizon: the blow-up check runs every step regardless
  Scenario s = sc;
  s.duration = s.frame_interval = stability_horizon(sc);
  s.snapshot_interval = 0;
  const cloth::Model model = cloth::build_model(s.scene);
  const EngineRun run = run_engine(s, e, model, nullptr, false);
  if (!run.stable && cause) *cause = run.timed_out ? "timeout" : run.cause;
  if (steps) *steps += run.counters.steps;
  return run.stable;
}

StabilityBracket search_stability_limit(const Scenario& sc, const EngineSpec& engine,
                                        std::optional<cloth::Integrator> integrator,
                                        long long n_start, long long n_min, double rel_tol) {
  Search search(sc, engine, integrator);
  // bracket on the step grid first, from the engine's own dt
  if (search.stable(n_start))
    search.grow(n_start, n_min);
  else
    search.shrink(n_start);
  search.bisect(rel_tol);
  search.bracket().n_start = n_start;
  return search.bracket();
}

}  // namespace clothbench
