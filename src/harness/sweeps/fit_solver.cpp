#include "harness/sweeps/fit_solver.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace clothbench {

const char* fit_status_name(FitStatus s) {
  switch (s) {
    case FitStatus::converged:
      return "converged";
    case FitStatus::unreachable:
      return "unreachable";
    case FitStatus::budget:
      return "budget";
    case FitStatus::failed:
      return "failed";
  }
  return "failed";
}

namespace {

/// Parameters closer than this in log (1 %) are one: the range is used up.
constexpr double kLogGap = 0.01;

/// A metric that moves by less than this fraction of itself per e-fold of the parameter (d ln m
/// / d ln p) has stopped moving: a plateau, such as a link stiffness at its cap.
constexpr double kPlateau = 0.01;

/// A run in log parameter: u = ln p, g = how far it misses the target (Solver::miss; NaN: no
/// metric).
struct Point {
  double u = 0.0;
  double g = NAN;
  bool ok() const { return std::isfinite(g); }
};

/// The solver's state: the runs so far, the range left (shrunk by runs that gave no metric).
class Solver {
 public:
  Solver(const std::function<double(double)>& metric, const FitSolverOptions& o)
      : m_metric(metric), m_o(o) {
    m_lo = std::log(o.lo > 0.0 ? o.lo : o.start / 1e4);
    m_hi = std::log(std::isfinite(o.hi) ? o.hi : o.start * 1e4);
    m_tol = o.relative ? o.tolerance * std::abs(o.target) : o.tolerance;
  }

  FitResult solve();

 private:
  /// Runs at u (within the range); stop is set when it converged or the budget is spent.
  Point run(double u) {
    u = std::clamp(u, m_lo, m_hi);
    const double m = m_metric(parameter(u));
    m_result.samples.push_back({parameter(u), m});
    Point p{u, miss(m)};
    if (p.ok() && std::abs(m - m_o.target) <= m_tol)
      m_stop = FitStatus::converged;
    else if (int(m_result.samples.size()) >= m_o.max_runs)
      m_stop = FitStatus::budget;
    return p;
  }
  /// The parameter at u: exactly the start or a given bound there (exp(log(1000)) is not 1000).
  double parameter(double u) const {
    for (const double p : {m_o.start, m_o.lo, m_o.hi})
      if (p > 0.0 && std::isfinite(p) && u == std::log(p)) return p;
    return std::exp(u);
  }

  /// How far m misses the target: in log metric for a positive target (power laws become
  /// straight lines in log-log, where secant steps land at once), else the difference.
  double miss(double m) const {
    if (!(m_o.target > 0.0)) return m - m_o.target;
    return std::log(std::max(m, m_o.target * 1e-12)) - std::log(m_o.target);
  }
  std::optional<Point> first_good(Point& a);
  bool bracket(Point& a, Point& b);
  void close(Point a, Point b);
  void finish(FitStatus status, const std::string& note);

  const std::function<double(double)>& m_metric;
  const FitSolverOptions& m_o;
  double m_lo, m_hi, m_tol;
  bool m_lo_bad = false, m_hi_bad = false;  // a run at that end of the range gave no metric
  std::optional<FitStatus> m_stop;
  FitResult m_result;
};

/// A first run that gives a metric: the start, else steps down, then up, from it.
std::optional<Point> Solver::first_good(Point& a) {
  const double h = std::log(m_o.first_factor);
  const double start = std::log(m_o.start);
  for (const double u : {start, start - h, start + h, start - 2 * h}) {
    a = run(u);
    if (a.ok() || m_stop) return a.ok() ? std::optional<Point>(a) : std::nullopt;
    // a run without a metric bounds the range on its side of the start
    if (u > start) {
      m_hi = std::min(m_hi, u);
      m_hi_bad = true;
    } else if (u < start) {
      m_lo = std::max(m_lo, u);
      m_lo_bad = true;
    }
  }
  return std::nullopt;
}

/// Grows a bracket from a: on return true, a and b have metrics on either side of the target
/// (or one converged); false when the target is out of reach or the budget is spent.
bool Solver::bracket(Point& a, Point& b) {
  double h = std::log(m_o.first_factor);
  std::optional<Point> prev;  // the run before a, for a slope
  while (!m_stop) {
    // secant direction once there is a slope, else "metric grows with the parameter"
    double step = a.g > 0 ? -h : h;
    if (prev && prev->ok() && a.g != prev->g) {
      const double secant = -a.g * (a.u - prev->u) / (a.g - prev->g);
      step = std::clamp(1.3 * secant, -h, h);
    }
    double u = a.u + step;
    // a bound where a run gave no metric is not run again: half way to it instead
    if (u >= m_hi && m_hi_bad) u = (a.u + m_hi) / 2;
    if (u <= m_lo && m_lo_bad) u = (a.u + m_lo) / 2;
    u = std::clamp(u, m_lo, m_hi);
    if (std::abs(u - a.u) < kLogGap) {
      finish(FitStatus::unreachable, m_hi_bad || m_lo_bad
                                         ? "runs further on give no metric (they blow up)"
                                         : "the target lies beyond the parameter's range");
      return false;
    }
    b = run(u);
    if (m_stop) return b.ok();
    if (!b.ok()) {
      // no metric here (a blow-up): the range ends here
      (u > a.u ? m_hi_bad : m_lo_bad) = true;
      (u > a.u ? m_hi : m_lo) = u;
      continue;
    }
    if ((a.g < 0) != (b.g < 0)) return true;
    // the metric no longer moves: a plateau the parameter cannot leave
    const double scale = m_o.target > 0.0 ? 1.0 : std::max(m_tol, std::abs(m_o.target));
    if (std::abs(b.g) <= std::abs(a.g) && std::abs(b.u - a.u) >= std::log(2.0) &&
        std::abs(b.g - a.g) < kPlateau * scale * std::abs(b.u - a.u)) {
      finish(FitStatus::unreachable, "the metric stops changing with the parameter");
      return false;
    }
    prev = a;
    if (std::abs(b.g) < std::abs(a.g)) {
      a = b;
      h *= 2;
    } else {
      prev = b;  // the wrong way: the slope now points back past a
    }
  }
  return false;
}

/// Closes the bracket [a, b] (metrics on either side of the target) by Illinois steps.
void Solver::close(Point a, Point b) {
  while (!m_stop) {
    const double u = (a.u * b.g - b.u * a.g) / (b.g - a.g);
    const Point c = run(std::isfinite(u) ? u : (a.u + b.u) / 2);
    if (m_stop) return;
    if (!c.ok()) return finish(FitStatus::unreachable, "a run inside the bracket gave no metric");
    if ((c.g < 0) != (b.g < 0)) {
      a = b;
    } else {
      a.g /= 2;  // Illinois: the end that stays loses half its weight
    }
    b = c;
  }
}

void Solver::finish(FitStatus status, const std::string& note) {
  if (!m_stop) m_stop = status;
  if (m_result.note.empty()) m_result.note = note;
}

FitResult Solver::solve() {
  Point a, b;
  if (first_good(a) && !m_stop && bracket(a, b) && !m_stop) close(a, b);
  if (!m_stop) m_stop = FitStatus::failed;
  FitResult& r = m_result;
  r.status = *m_stop;
  // the best run, and the slope between the two good runs nearest it in log parameter
  std::vector<FitSample> good;
  for (const FitSample& s : r.samples)
    if (std::isfinite(s.metric)) good.push_back(s);
  r.metric = NAN;
  r.sensitivity = NAN;
  if (good.empty()) {
    r.status = FitStatus::failed;
    r.parameter = r.samples.empty() ? m_o.start : r.samples.back().parameter;
    if (r.note.empty()) r.note = "no run gave the metric";
    return r;
  }
  const auto miss = [&](const FitSample& s) { return std::abs(s.metric - m_o.target); };
  const FitSample best =
      *std::min_element(good.begin(), good.end(),
                        [&](const FitSample& x, const FitSample& y) { return miss(x) < miss(y); });
  r.parameter = best.parameter;
  r.metric = best.metric;
  std::sort(good.begin(), good.end(), [&](const FitSample& x, const FitSample& y) {
    return std::abs(std::log(x.parameter / best.parameter)) <
           std::abs(std::log(y.parameter / best.parameter));
  });
  for (size_t k = 1; k < good.size() && std::isnan(r.sensitivity); ++k)
    if (good[k].parameter != good[0].parameter)
      r.sensitivity = (good[k].metric - good[0].metric) / (good[k].parameter - good[0].parameter);
  if (r.note.empty())
    r.note = r.status == FitStatus::converged ? "within tolerance"
             : r.status == FitStatus::budget  ? "the run budget is spent"
                                              : "no run gave the metric";
  return r;
}

}  // namespace

FitResult solve_monotone(const std::function<double(double)>& metric, const FitSolverOptions& o) {
  return Solver(metric, o).solve();
}

}  // namespace clothbench
