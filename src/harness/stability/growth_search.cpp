#include "harness/stability/growth_search.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>

#include "cloth/model/spring_set.hpp"
#include "harness/engines/engine_factory.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/run/runner.hpp"
#include "harness/scenario/scenario_format.hpp"
#include "harness/sweeps/sweep.hpp"

namespace clothbench {

namespace {

/// Sub-steps of the physical map: the same time as one step of dt, in steps of dt / 8.
constexpr int kPhysicalSubsteps = 8;

/// The engine of the configuration at time step dt (engines may prepare for their dt when
/// built, as bullet-softbody's matched stiffness and the projective solver's factor do).
std::unique_ptr<cloth::Simulator> engine_at(const Scenario& sc, const EngineSpec& e, double dt) {
  EngineSpec spec = e;
  spec.dt = dt;
  return make_engine(spec, engine_scene(sc, spec));
}

/// The growth of the physical map at state s: the same time as one step of dt, in steps of
/// dt / 8; adds its engine steps to steps.
cloth::GrowthEstimate physical_growth(const Scenario& sc, const EngineSpec& e,
                                      const cloth::Model& model, const GrowthState& s, double dt,
                                      const cloth::GrowthOptions& go, long long* steps) {
  const double h = dt / kPhysicalSubsteps;
  auto fine = engine_at(sc, e, h);
  const cloth::GrowthEstimate phys =
      cloth::estimate_growth(*fine, s.state, h, kPhysicalSubsteps, model.free, go);
  *steps += static_cast<long long>(phys.products) * kPhysicalSubsteps;
  return phys;
}

/// The growth at one state: the one-step map, then (when its guaranteed rate, lower_rate, is
/// past the tolerance) the physical map in sub-steps. Each estimate stops as soon as its side
/// of the verdict's threshold is decided (cloth::GrowthOptions::decide_below): the one-step
/// map's once it is below the tolerance (above it, its rate is the next threshold and is
/// measured in full), the physical map's once it is on either side of
/// sigma_low(dt) - growth_tol.
StateGrowth judge_state(const Scenario& sc, const EngineSpec& e, const cloth::Model& model,
                        const GrowthState& s, double dt, const GrowthSearchOptions& o,
                        long long* steps) {
  cloth::GrowthOptions go;
  go.perturbation = o.perturbation;
  StateGrowth g;
  g.label = s.label;
  g.contacts = s.contacts;
  auto sim = engine_at(sc, e, dt);
  if (o.decide_early) go.decide_below = std::exp(o.growth_tol * dt);
  g.estimate = cloth::estimate_growth(*sim, s.state, dt, 1, model.free, go);
  *steps += g.estimate.products;
  g.smooth = g.estimate.smooth;
  g.nonsmooth_reason = g.estimate.nonsmooth_reason;
  g.rate = g.estimate.rate;
  g.lower_rate = lower_rate(g.estimate, dt);
  if (!g.smooth || !(g.lower_rate > o.growth_tol)) return g;
  if (interrupt_requested()) throw Interrupted();

  // the physical growth over the same time: unstable when below sigma_low(dt) - growth_tol
  if (o.decide_early)
    go.decide_below = go.decide_above = std::exp((g.lower_rate - o.growth_tol) * dt);
  const cloth::GrowthEstimate phys = physical_growth(sc, e, model, s, dt, go, steps);
  g.physical_decided = phys.decided != 0;
  if (!phys.smooth) {
    // no physical rate to compare with: no verdict at this state
    g.smooth = false;
    g.nonsmooth_reason = "in steps of dt / 8: " + phys.nonsmooth_reason;
    return g;
  }
  g.physical_rate = phys.rate;
  g.unstable = g.lower_rate - std::max(g.physical_rate, 0.0) > o.growth_tol;
  return g;
}

/// "; near the physics: ..." when the unstable states' excess over their physical rates is at
/// most kNearPhysicalFraction of their rates (largest_excess), else "".
std::string near_physics_note(const std::vector<StateGrowth>& unstable) {
  double fraction = 0;
  const int i = largest_excess(unstable, &fraction);
  if (i < 0 || !(fraction <= kNearPhysicalFraction)) return "";
  const StateGrowth* g = &unstable[size_t(i)];
  return "; near the physics: no state grows more than " +
         std::to_string(static_cast<int>(std::ceil(100 * fraction))) +
         "% faster than its physical rate ('" + g->label + "' at " + format_double(g->rate) +
         "/s against " + format_double(g->physical_rate) +
         "/s); the estimates' error or the scheme's accuracy on a growing mode explains that "
         "as well as a step-size instability: compare with --method blowup";
}

/// The verdict on a time step: unstable when a smooth state is; none when no state is smooth.
enum class Verdict { stable, unstable, nonsmooth };

/// A search that has used its wall-clock budget.
struct OutOfTime {};

Verdict verdict_of(const std::vector<StateGrowth>& states) {
  bool any_smooth = false;
  for (const StateGrowth& g : states) {
    if (g.smooth && g.unstable) return Verdict::unstable;
    any_smooth = any_smooth || g.smooth;
  }
  return any_smooth ? Verdict::stable : Verdict::nonsmooth;
}

/// The search's bracket and the states judged at its ends.
class GrowthSearch {
 public:
  GrowthSearch(const Scenario& sc, const EngineSpec& e, const std::vector<GrowthState>& states,
               const GrowthSearchOptions& o)
      : m_sc(sc),
        m_e(e),
        m_model(cloth::build_model(sc.scene)),
        m_states(states),
        m_o(o),
        m_started(std::chrono::steady_clock::now()) {}

  /// Judges dt; throws OutOfTime, after the first time step, once the search has taken more
  /// than its budget.
  Verdict judge(double dt) {
    if (interrupt_requested()) throw Interrupted();
    if (m_limit.judged > 0 && m_o.max_seconds > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_started).count() >
            m_o.max_seconds)
      throw OutOfTime();
    // a time step judged before (the bracket halving back to its start) is not judged again
    if (const auto it = m_judged.find(dt); it != m_judged.end()) {
      m_last = it->second;
    } else {
      ++m_limit.judged;
      m_last = judge_growth(m_sc, m_e, m_model, m_states, dt, m_o, &m_limit.steps);
      m_judged[dt] = m_last;
    }
    const Verdict v = verdict_of(m_last);
    if (v == Verdict::unstable) {
      m_limit.first_unstable_dt = dt;
      m_unstable = m_last;
    } else if (v == Verdict::stable) {
      m_limit.stable_dt = dt;
    } else {
      m_nonsmooth_dt = dt;
    }
    return v;
  }

  /// Brackets from dt_start: a first step of first_step either way (the start, the
  /// prediction, is mostly within a few per cent of the limit), then doubling while stable,
  /// halving while unstable down to dt_start / 2^max_halvings.
  void bracket(double dt_start) {
    double dt = std::min(dt_start, m_o.dt_max), step = m_o.first_step;
    Verdict v = judge(dt);
    const bool unstable_at_start = v == Verdict::unstable;
    for (; v == Verdict::stable && dt < m_o.dt_max; step = 2) {
      dt = std::min(step * dt, m_o.dt_max);
      v = judge(dt);
    }
    // unstable past a stable start: bracketed already
    if (!unstable_at_start) return;
    const double lowest = std::min(dt_start, m_o.dt_max) * std::ldexp(1.0, -m_o.max_halvings);
    for (step = m_o.first_step; v == Verdict::unstable && dt > lowest * (1 + 1e-12); step = 2) {
      dt /= step;
      v = judge(dt);
    }
  }

  /// Bisects on a log scale down to rel_tol.
  void bisect() {
    GrowthLimit& l = m_limit;
    while (std::isfinite(l.stable_dt) && std::isfinite(l.first_unstable_dt) &&
           l.first_unstable_dt / l.stable_dt - 1 > m_o.rel_tol && m_nonsmooth_dt == 0) {
      if (judge(std::sqrt(l.stable_dt * l.first_unstable_dt)) == Verdict::nonsmooth) break;
    }
  }

  /// The limit found; timed_out: the search stopped at its budget.
  GrowthLimit finish(bool timed_out = false) {
    GrowthLimit& l = m_limit;
    StateGrowth* worst = nullptr;
    for (StateGrowth& g : m_unstable)
      if (g.smooth && g.unstable && (!worst || g.rate > worst->rate)) worst = &g;
    if (worst) {
      // the row's physical rate in full, and the cause's (near_physics_note) with it
      measure_in_full(*worst);
      l.growth_rate = worst->rate;
      l.physical_rate = worst->physical_rate;
      l.mode = worst->estimate.mode;
      const GrowthState& s = state(worst->label);
      l.mode_energy = mode_energy_by_kind(m_model, s.state.x, l.mode);
    }
    if (!timed_out) measure_largest_excess_in_full();
    l.cause = timed_out ? timeout_cause() : cause();
    return l;
  }

 private:
  const GrowthState& state(const std::string& label) const {
    return *std::find_if(m_states.begin(), m_states.end(),
                         [&](const GrowthState& s) { return s.label == label; });
  }

  /// The physical rates near_physics_note compares with, in full: while the state of the
  /// largest excess has a rate stopped once its side was decided, that one is measured again.
  void measure_largest_excess_in_full() {
    double fraction = 0;
    for (int i = largest_excess(m_unstable, &fraction);
         i >= 0 && m_unstable[size_t(i)].physical_decided;
         i = largest_excess(m_unstable, &fraction))
      measure_in_full(m_unstable[size_t(i)]);
  }

  /// Measures state g's physical rate at first_unstable_dt in full when it was stopped once its
  /// side was decided (it is only that precise); an engine that fails keeps the stopped one.
  void measure_in_full(StateGrowth& g) {
    if (!g.physical_decided) return;
    cloth::GrowthOptions go;
    go.perturbation = m_o.perturbation;
    try {
      g.physical_rate = physical_growth(m_sc, m_e, m_model, state(g.label),
                                        m_limit.first_unstable_dt, go, &m_limit.steps)
                            .rate;
    } catch (const cloth::EngineFailure&) {
    }
    g.physical_decided = false;
  }

  /// A search stopped by its budget: what it has is a bound, or an unfinished bracket.
  std::string timeout_cause() const {
    const std::string c = "timeout after --max-run-seconds " + format_double(m_o.max_seconds) +
                          " s with " + std::to_string(m_limit.judged) + " time steps judged";
    if (m_unstable.empty() && m_nonsmooth_dt == 0) return c + ": growth_stable_dt is a lower bound";
    return c + ": the bracket is unfinished; " + cause();
  }

  /// Which states grow at first_unstable_dt: only those in contact, or free ones too.
  std::string cause() const {
    std::string free_unstable, contact_unstable, free_stable, nonsmooth;
    for (const StateGrowth& g : m_unstable.empty() ? m_last : m_unstable) {
      const std::string what = "'" + g.label + "' at " + format_double(g.rate) + "/s";
      if (!g.smooth)
        nonsmooth += (nonsmooth.empty() ? "" : " ") + g.label + ": " + g.nonsmooth_reason;
      else if (g.unstable && g.contacts > 0)
        contact_unstable += (contact_unstable.empty() ? "" : " ") + what;
      else if (g.unstable)
        free_unstable += (free_unstable.empty() ? "" : " ") + what;
      else if (g.contacts == 0)
        free_stable += (free_stable.empty() ? "'" : " '") + g.label + "'";
    }
    std::string c;
    if (m_unstable.empty() && m_nonsmooth_dt > 0)
      c = "non-smooth at every state at dt = " + format_double(m_nonsmooth_dt) + " s";
    else if (m_unstable.empty())
      c = "no growth past the tolerance up to --dt-max = " + format_double(m_o.dt_max) +
          " s: growth_stable_dt is a lower bound";
    else if (!contact_unstable.empty() && free_unstable.empty() && !free_stable.empty())
      c = "set by contact: the state in contact grows (" + contact_unstable +
          "); the free states (" + free_stable + ") do not";
    else
      c = "free: grows at " + free_unstable +
          (contact_unstable.empty() ? "" : "; and in contact: " + contact_unstable);
    if (!nonsmooth.empty()) c += "; non-smooth: " + nonsmooth;
    if (!m_unstable.empty()) c += near_physics_note(m_unstable);
    return c;
  }

  const Scenario& m_sc;
  const EngineSpec& m_e;
  cloth::Model m_model;
  const std::vector<GrowthState>& m_states;
  GrowthSearchOptions m_o;
  std::chrono::steady_clock::time_point m_started;
  GrowthLimit m_limit;
  std::vector<StateGrowth> m_last, m_unstable;
  std::map<double, std::vector<StateGrowth>> m_judged;  // by time step (s)
  double m_nonsmooth_dt = 0;
};

}  // namespace

double lower_rate(const cloth::GrowthEstimate& e, double dt, int steps) {
  if (e.converged || !std::isfinite(e.rho) || !std::isfinite(e.residual)) return e.rate;
  const double low = e.rho - std::sqrt(e.residual);
  return low > 0 ? std::log(low) / (steps * dt) : -std::numeric_limits<double>::infinity();
}

int largest_excess(const std::vector<StateGrowth>& states, double* fraction) {
  int worst = -1;
  *fraction = std::numeric_limits<double>::quiet_NaN();
  for (size_t i = 0; i < states.size(); ++i) {
    const StateGrowth& g = states[i];
    if (!g.smooth || !g.unstable) continue;
    const double f = (g.rate - std::max(g.physical_rate, 0.0)) / g.rate;
    if (worst < 0 || f > *fraction) {
      worst = static_cast<int>(i);
      *fraction = f;
    }
  }
  return worst;
}

std::vector<StateGrowth> judge_growth(const Scenario& sc, const EngineSpec& engine,
                                      const cloth::Model& model,
                                      const std::vector<GrowthState>& states, double dt,
                                      const GrowthSearchOptions& o, long long* steps) {
  std::vector<StateGrowth> out;
  for (const GrowthState& s : states) {
    // an engine that cannot go on (an external program that died) gives no verdict there
    try {
      out.push_back(judge_state(sc, engine, model, s, dt, o, steps));
    } catch (const cloth::EngineFailure& e) {
      StateGrowth g;
      g.label = s.label;
      g.contacts = s.contacts;
      g.smooth = false;
      g.nonsmooth_reason = std::string("engine failed: ") + e.what();
      out.push_back(g);
    }
  }
  return out;
}

GrowthLimit search_growth_limit(const Scenario& sc, const EngineSpec& engine,
                                const std::vector<GrowthState>& states, double dt_start,
                                const GrowthSearchOptions& o) {
  GrowthSearch search(sc, engine, states, o);
  try {
    search.bracket(dt_start);
    search.bisect();
  } catch (const OutOfTime&) {
    return search.finish(true);
  }
  return search.finish();
}

std::array<double, 3> mode_energy_by_kind(const cloth::Model& model, const cloth::Matrix3X& x,
                                          const cloth::Matrix3X& u) {
  std::array<double, 3> e{0, 0, 0};
  cloth::for_each_spring(model.springs, [&](int p, int q, size_t g, int s) {
    const cloth::Vector3 d = (x.col(q) - x.col(p)).normalized();
    const double stretch = d.dot(u.col(q) - u.col(p));
    e[static_cast<size_t>(model.springs.kind(g, s))] +=
        0.5 * model.springs.stiffness(g, s) * stretch * stretch;
  });
  const double sum = e[0] + e[1] + e[2];
  for (double& v : e) v = sum > 0 ? v / sum : std::numeric_limits<double>::quiet_NaN();
  return e;
}

}  // namespace clothbench
