#include "harness/gate/ensemble_runs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "harness/gate/ensemble_size.hpp"
#include "harness/gate/run_figures.hpp"
#include "harness/gate/welch_test.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/engine_metric.hpp"
#include "harness/run/run_parallel.hpp"

namespace clothbench {

EnsembleMembers::EnsembleMembers(const Scenario& sc, const Tolerances& tol, const RunResult& run0,
                                 const EngineShapes& shapes, int jobs, std::uint64_t seed)
    : m_sc(sc), m_tol(tol), m_shapes(shapes), m_jobs(jobs), m_seed(seed) {
  summarize(0, run0);
}

void EnsembleMembers::summarize(int member, const RunResult& r) {
  for (size_t i = 0; i < r.runs.size(); ++i) {
    const EngineRun& run = r.runs[i];
    if (!m_tol.ensemble.count(run.spec.name)) continue;
    std::vector<End>& ends = m_ends[run.spec.name];
    if (ends.size() != size_t(member)) continue;  // the reference of a member run, or a repeat
    End e;
    e.values = run_metrics(r, i);
    for (const TestMetric& row : test_metrics(r, run)) e.values["test." + row.metric] = row.value;
    const auto it = m_shapes.find(run.spec.name);
    e.values["final_shape_rms"] =
        it == m_shapes.end() ? NAN : shape_rms(run.snapshots.back(), it->second);
    e.start = run.snapshots.front(), e.end = run.snapshots.back(), e.t_end = run.frames.back().t;
    ends.push_back(std::move(e));
  }
}

void EnsembleMembers::run_up_to(const EnsembleSizes& sizes) {
  // the members still to run, each with the engines that lack it
  std::map<int, std::vector<std::string>> todo;
  for (const auto& [engine, n] : sizes)
    for (int m = count(engine); m < n; ++m) todo[m].push_back(engine);
  std::vector<std::pair<int, std::vector<std::string>>> jobs(todo.begin(), todo.end());
  std::vector<RunResult> results(jobs.size());
  std::vector<double> seconds(jobs.size());
  run_parallel(int(jobs.size()), m_jobs, [&](int k) {
    const auto t0 = std::chrono::steady_clock::now();
    RunOptions ro;
    ro.progress = false;
    ro.engines = jobs[size_t(k)].second;
    ro.member = jobs[size_t(k)].first;
    ro.member_seed = m_seed;
    results[size_t(k)] = run_scenario(m_sc, ro);
    seconds[size_t(k)] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  });
  // in member order, so that each engine's members stay in order
  for (size_t k = 0; k < jobs.size(); ++k) {
    summarize(jobs[k].first, results[k]);
    for (const std::string& engine : jobs[k].second) m_seconds[engine].push_back(seconds[k]);
  }
}

int EnsembleMembers::count(const std::string& engine) const {
  const auto it = m_ends.find(engine);
  return it == m_ends.end() ? 0 : int(it->second.size());
}

double EnsembleMembers::member_seconds(const std::string& engine) const {
  const auto it = m_seconds.find(engine);
  if (it == m_seconds.end() || it->second.empty()) return 0;
  double sum = 0;
  for (double s : it->second) sum += s;
  return sum / double(it->second.size());
}

EnsembleValues EnsembleMembers::values(const EnsembleSizes& sizes) const {
  EnsembleValues values;
  for (const auto& [engine, e] : m_tol.ensemble) {
    const auto size = sizes.find(engine);
    if (size == sizes.end()) continue;
    const int n = size->second;
    if (count(engine) < std::max(n, 2))
      throw std::logic_error("ensemble of " + engine + ": members asked for but not run");
    const std::vector<End>& ends = m_ends.at(engine);
    for (const std::string& q : e.quantities)
      for (int m = 0; m < n; ++m) {
        const std::map<std::string, double>& measured = ends[size_t(m)].values;
        const auto it = measured.find(q);
        if (it == measured.end())
          throw UserError("tolerances.toml: ensemble." + engine + ": \"" + q +
                          "\" is not measured in this scenario (a [test] metric it lacks?)");
        values[engine + "/" + q].push_back(it->second);
      }
    const End &a = ends[0], &b = ends[1];
    values[engine + "/growth_exponent"] = {
        growth_exponent(a.start, b.start, a.end, b.end, std::min(a.t_end, b.t_end))};
  }
  return values;
}

EnsembleSizes recorded_sizes(const Tolerances& tol, const EnsembleValues& recorded) {
  EnsembleSizes sizes;
  for (const auto& [engine, e] : tol.ensemble) {
    if (e.members > 0) {
      sizes[engine] = e.members;
      continue;
    }
    const auto it = recorded.find(engine + "/" + *e.quantities.begin());
    // none recorded: the pilot's count runs, and the gate fails for want of a baseline
    sizes[engine] = it == recorded.end() ? kPilotMembers : std::max(int(it->second.size()), 2);
  }
  return sizes;
}

double finite_spread(const std::vector<double>& v) {
  std::vector<double> f;
  for (double x : v)
    if (std::isfinite(x)) f.push_back(x);
  if (f.size() < 2) return NAN;
  double mean = 0, sd = 0;
  sample_moments(f, mean, sd);
  return sd;
}

namespace {

/// The members engine e's goals need, from the spread of the members run so far (at most the
/// cap); fills the choice's cap, member time and whether the cap binds.
int members_for_goals(const EnsembleMembers& members, const std::string& engine,
                      const Tolerances::Ensemble& e, double alpha, EnsembleChoice& c) {
  c.member_seconds = members.member_seconds(engine);
  const double cap = c.member_seconds > 0 ? std::floor(e.max_seconds / c.member_seconds) : 1000;
  c.cap = int(std::clamp(cap, double(kMinChosenMembers), 1000.0));
  const EnsembleValues v = members.values({{engine, members.count(engine)}});
  int need = kMinChosenMembers;
  c.capped = false;
  for (const auto& [q, shift] : e.detect) {
    const double sd = finite_spread(v.at(engine + "/" + q));
    if (std::isnan(sd)) continue;  // undefined in (almost) every member: nothing to size
    const int n = members_needed(sd, shift, alpha, kMinChosenMembers, c.cap);
    if (n == 0) c.capped = true;
    need = std::max(need, n == 0 ? c.cap : n);
  }
  return need;
}

/// The recorded members are the first n of those run, whose spread is not that of all of
/// them: from n on, the fewest first members (up to all run, and no more than the cap) that
/// reach every goal, and what they catch by quantity.
int fewest_reaching(const EnsembleMembers& members, const std::string& engine,
                    const Tolerances::Ensemble& e, double alpha, int n, int cap,
                    std::map<std::string, double>& detectable) {
  const int run = std::max(n, std::min(members.count(engine), cap));
  for (;; ++n) {
    const EnsembleValues v = members.values({{engine, n}});
    bool reached = true;
    for (const auto& [q, shift] : e.detect) {
      detectable[q] = detectable_shift(finite_spread(v.at(engine + "/" + q)), n, alpha);
      if (detectable[q] > shift) reached = false;
    }
    if (reached || n >= run) return n;
  }
}

}  // namespace

std::map<std::string, EnsembleChoice> choose_sizes(EnsembleMembers& members, const Tolerances& tol,
                                                   double alpha, bool progress,
                                                   EnsembleSizes& sizes) {
  sizes.clear();
  for (const auto& [engine, e] : tol.ensemble)
    sizes[engine] = e.members > 0 ? e.members : kPilotMembers;
  members.run_up_to(sizes);
  std::map<std::string, EnsembleChoice> choices;
  // the spread of more members can ask for more still: a few rounds, each on all run so far
  for (int round = 0; round < 4; ++round) {
    bool more = false;
    for (const auto& [engine, e] : tol.ensemble) {
      if (e.members > 0) continue;
      EnsembleChoice& c = choices[engine];
      const int need = members_for_goals(members, engine, e, alpha, c);
      sizes[engine] = need;
      if (need <= members.count(engine)) continue;
      more = true;
      if (progress)
        std::fprintf(
            stderr, "ensemble of %s: the spread of %d members asks for %d%s; running %d more\n",
            engine.c_str(), members.count(engine), need,
            c.capped ? " (the most max_seconds allows)" : "", need - members.count(engine));
    }
    if (!more) break;
    members.run_up_to(sizes);
  }
  for (auto& [engine, c] : choices) {
    const Tolerances::Ensemble& e = tol.ensemble.at(engine);
    c.members = sizes[engine] =
        fewest_reaching(members, engine, e, alpha, sizes[engine], c.cap, c.detectable);
    // a goal missed now is one the cap keeps out of reach
    c.capped = false;
    for (const auto& [q, shift] : e.detect) c.capped = c.capped || c.detectable.at(q) > shift;
  }
  return choices;
}

}  // namespace clothbench
