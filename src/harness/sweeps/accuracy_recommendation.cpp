#include "harness/sweeps/accuracy_recommendation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include "cloth/model/constants.hpp"

namespace clothbench {

namespace {

using cloth::kNaN;

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
  if (std::isnan(engine_cost(a)) != std::isnan(engine_cost(b))) return std::isnan(engine_cost(b));
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

}  // namespace

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
  // a NaN cost or error never wins: it ranks after every number
  const auto less = [](double a, double b) { return a < b || (std::isnan(b) && !std::isnan(a)); };
  const Recommendation* best = nullptr;
  for (const Recommendation& r : out) {
    if (!r.found) continue;
    if (!best || less(key(r.row), key(best->row)) ||
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

}  // namespace clothbench
