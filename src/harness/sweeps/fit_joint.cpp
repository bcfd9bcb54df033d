#include "harness/sweeps/fit_joint.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace clothbench {

namespace {

/// Steps shorter than this in ln p (in every parameter, 1 %) have stalled.
constexpr double kStalledLogStep = 0.01;

/// The damping of the first step, relative to the diagonal of J^T J: nearly Gauss-Newton.
constexpr double kFirstDamping = 1e-3;

/// Damping past this (relative) leaves steps too short to matter: the steps have stalled.
constexpr double kMaxDamping = 1e6;

/// An evaluation in ln p: its metrics, residuals (units of tolerance) and their squared sum.
struct Evaluation {
  Eigen::VectorXd u, m, r;
  double cost = std::numeric_limits<double>::infinity();
  bool ok = false;    // every metric given
  size_t sample = 0;  // its index in the samples
};

/// The solver's state: the evaluations so far, the Jacobian d r / d u and the best point.
class JointSolver {
 public:
  JointSolver(const JointMetrics& metrics, const JointFitOptions& o)
      : m_metrics(metrics), m_o(o), m_lo(o.lo.array().log()), m_hi(o.hi.array().log()) {}

  JointFitResult solve();

 private:
  Evaluation run(const Eigen::VectorXd& u);
  double residual(int i, double m) const;
  double residual_slope(int i, double m) const;
  bool within(const Eigen::VectorXd& m) const;
  void differences(const Evaluation& x);
  Eigen::VectorXd step(const Evaluation& x, double damping) const;
  void broyden(const Evaluation& a, const Evaluation& b);
  void iterate(Evaluation x);
  std::string bound_note(const Evaluation& x) const;
  void finish(FitStatus status, const std::string& note);
  JointFitResult result() const;

  const JointMetrics& m_metrics;
  const JointFitOptions& m_o;
  Eigen::VectorXd m_lo, m_hi;  // #N ln of the ranges
  Eigen::MatrixXd m_J;         // #M by #N d residual / d ln p
  std::optional<FitStatus> m_stop;
  std::string m_note;
  std::vector<JointSample> m_samples;
  Evaluation m_best;              // least cost, or the converged one
  bool m_no_metric_seen = false;  // some evaluation gave no metric
};

/// How far metric i misses its target, in units of its tolerance: in ln metric for a positive
/// target (ln(1 + tol / target) is one unit), else the difference.
double JointSolver::residual(int i, double m) const {
  const double t = m_o.target[i], tol = m_o.tolerance[i];
  if (!(t > 0.0)) return (m - t) / tol;
  return std::log(std::max(m, t * 1e-12) / t) / std::log1p(tol / t);
}

/// d residual / d metric at m.
double JointSolver::residual_slope(int i, double m) const {
  const double t = m_o.target[i], tol = m_o.tolerance[i];
  if (!(t > 0.0)) return 1.0 / tol;
  return 1.0 / (std::max(m, t * 1e-12) * std::log1p(tol / t));
}

bool JointSolver::within(const Eigen::VectorXd& m) const {
  return ((m - m_o.target).array().abs() <= m_o.tolerance.array()).all();
}

/// One evaluation at u (clamped to the ranges); stop is set when it converged or the budget
/// is spent.
Evaluation JointSolver::run(const Eigen::VectorXd& u) {
  Evaluation x;
  x.u = u.cwiseMax(m_lo).cwiseMin(m_hi);
  const Eigen::VectorXd p = x.u.array().exp();
  // the ends exactly as given (exp(log(1000)) is not 1000)
  Eigen::VectorXd exact = p;
  for (Eigen::Index j = 0; j < p.size(); ++j)
    for (const double v : {m_o.lo[j], m_o.hi[j], m_o.start[j]})
      if (x.u[j] == std::log(v)) exact[j] = v;
  x.m = m_metrics(exact);
  x.sample = m_samples.size();
  m_samples.push_back({exact, x.m});
  x.ok = x.m.size() == m_o.target.size() && x.m.allFinite();
  if (x.ok) {
    x.r.resize(x.m.size());
    for (int i = 0; i < x.m.size(); ++i) x.r[i] = residual(i, x.m[i]);
    x.cost = x.r.squaredNorm();
  } else {
    m_no_metric_seen = true;
  }
  const bool converged = x.ok && within(x.m);
  if (x.ok && !(m_best.ok && within(m_best.m)) && (converged || x.cost < m_best.cost)) m_best = x;
  if (converged)
    finish(FitStatus::converged, "every metric within its tolerance");
  else if (int(m_samples.size()) >= m_o.max_runs)
    finish(FitStatus::budget, "the run budget is spent");
  return x;
}

/// The Jacobian at x by forward differences, one evaluation per parameter (backwards at the
/// top of a range or where forwards gives no metric; a zero column where neither does).
void JointSolver::differences(const Evaluation& x) {
  const Eigen::Index n = x.u.size();
  m_J.setZero(x.r.size(), n);
  for (Eigen::Index j = 0; j < n && !m_stop; ++j) {
    for (const double sign : {1.0, -1.0}) {
      double h = sign * m_o.difference_step;
      if (x.u[j] + h > m_hi[j] || x.u[j] + h < m_lo[j]) h = -h;
      Eigen::VectorXd u = x.u;
      u[j] += h;
      const Evaluation y = run(u);
      if (m_stop) return;
      const double du = y.u[j] - x.u[j];
      if (y.ok && du != 0.0) {
        m_J.col(j) = (y.r - x.r) / du;
        break;
      }
    }
  }
}

/// The damped Gauss-Newton step from x: (J^T J + damping diag(J^T J)) du = -J^T r over the
/// parameters free to move (one at an end of its range pushing outwards is held), at most
/// max_step in any parameter.
Eigen::VectorXd JointSolver::step(const Evaluation& x, double damping) const {
  const Eigen::Index n = x.u.size();
  const Eigen::MatrixXd A = m_J.transpose() * m_J;
  const Eigen::VectorXd g = m_J.transpose() * x.r;
  const double floor = 1e-9 * std::max(A.diagonal().maxCoeff(), 1e-300);
  std::vector<bool> free(size_t(n), true);
  Eigen::VectorXd du = Eigen::VectorXd::Zero(n);
  for (Eigen::Index pass = 0; pass <= n; ++pass) {
    // the free parameters' system
    std::vector<Eigen::Index> idx;
    for (Eigen::Index j = 0; j < n; ++j)
      if (free[size_t(j)]) idx.push_back(j);
    du.setZero();
    if (idx.empty()) break;
    const Eigen::Index k = Eigen::Index(idx.size());
    Eigen::MatrixXd Af(k, k);
    Eigen::VectorXd gf(k);
    for (Eigen::Index a = 0; a < k; ++a) {
      gf[a] = g[idx[size_t(a)]];
      for (Eigen::Index b = 0; b < k; ++b) Af(a, b) = A(idx[size_t(a)], idx[size_t(b)]);
      Af(a, a) += damping * (Af(a, a) + floor) + floor;
    }
    const Eigen::VectorXd df = Af.ldlt().solve(-gf);
    for (Eigen::Index a = 0; a < k; ++a) du[idx[size_t(a)]] = df[a];
    // hold a parameter at an end of its range that the step pushes outwards
    bool held = false;
    for (const Eigen::Index j : idx)
      if ((x.u[j] >= m_hi[j] && du[j] > 0) || (x.u[j] <= m_lo[j] && du[j] < 0)) {
        free[size_t(j)] = false;
        held = true;
      }
    if (!held) break;
  }
  const double longest = du.cwiseAbs().maxCoeff();
  if (longest > m_o.max_step) du *= m_o.max_step / longest;
  // the step as the ranges leave it
  return (x.u + du).cwiseMax(m_lo).cwiseMin(m_hi) - x.u;
}

/// Broyden's update of J from a to b: the secant (r_b - r_a) along u_b - u_a holds, J is
/// unchanged across it.
void JointSolver::broyden(const Evaluation& a, const Evaluation& b) {
  const Eigen::VectorXd du = b.u - a.u;
  const double d2 = du.squaredNorm();
  if (!(d2 > 0.0)) return;
  m_J += ((b.r - a.r) - m_J * du) * du.transpose() / d2;
}

/// Why the steps stalled at x: a parameter at an end of its range, or the targets' conflict.
std::string JointSolver::bound_note(const Evaluation& x) const {
  for (Eigen::Index j = 0; j < x.u.size(); ++j) {
    const bool top = x.u[j] >= m_hi[j] - kStalledLogStep,
               bottom = x.u[j] <= m_lo[j] + kStalledLogStep;
    if (!top && !bottom) continue;
    const std::string name =
        size_t(j) < m_o.names.size() ? m_o.names[size_t(j)] : "parameter " + std::to_string(j);
    return "the best lies at the " + std::string(top ? "top" : "bottom") + " of " + name +
           "'s range";
  }
  if (m_no_metric_seen) return "runs further on give no metric (they blow up)";
  return "the targets cannot all be met at once: the best is the least-squares compromise";
}

/// Damped steps from x until a stop (see the file comment).
void JointSolver::iterate(Evaluation x) {
  double damping = kFirstDamping;
  bool fresh = true;  // J from differences at x, no Broyden update since
  while (!m_stop) {
    const Eigen::VectorXd du = step(x, damping);
    if (du.cwiseAbs().maxCoeff() < kStalledLogStep || damping > kMaxDamping) {
      // stalled: once more with a Jacobian from differences, then give up
      if (fresh) return finish(FitStatus::unreachable, bound_note(x));
      differences(x);
      fresh = true;
      damping = kFirstDamping;
      continue;
    }
    const Evaluation y = run(x.u + du);
    if (m_stop) return;
    if (y.ok) {
      broyden(x, y);
      fresh = false;
    }
    if (y.ok && y.cost < x.cost) {
      x = y;
      damping = std::max(damping / 4, 1e-9);
    } else {
      // a worse point, or no metric there: shorter, steeper steps
      damping = std::max(damping, 1e-2) * (y.ok ? 4.0 : 10.0);
    }
  }
}

void JointSolver::finish(FitStatus status, const std::string& note) {
  if (!m_stop) m_stop = status;
  if (m_note.empty()) m_note = note;
}

JointFitResult JointSolver::result() const {
  JointFitResult r;
  r.samples = m_samples;
  r.status = m_stop.value_or(FitStatus::failed);
  r.note = m_note;
  const Eigen::Index nm = m_o.target.size(), np = m_o.start.size();
  r.sensitivity = Eigen::MatrixXd::Constant(nm, np, NAN);
  if (!m_best.ok) {
    r.status = FitStatus::failed;
    r.parameters = m_samples.empty() ? m_o.start : m_samples.front().parameters;
    r.metrics = Eigen::VectorXd::Constant(nm, NAN);
    if (r.note.empty() || m_samples.size() == 1)
      r.note = "the start gives no value of every metric";
    return r;
  }
  r.parameters = m_samples[m_best.sample].parameters;
  r.metrics = m_best.m;
  // d m_i / d p_j = (d r_i / d u_j) / (d r_i / d m_i) / p_j
  if (m_J.rows() == nm && m_J.cols() == np)
    for (Eigen::Index i = 0; i < nm; ++i)
      for (Eigen::Index j = 0; j < np; ++j)
        r.sensitivity(i, j) = m_J(i, j) / residual_slope(int(i), r.metrics[i]) / r.parameters[j];
  return r;
}

JointFitResult JointSolver::solve() {
  const Evaluation x = run(m_o.start.array().log());
  if (!m_stop && x.ok) {
    differences(x);
    if (!m_stop) iterate(x);
  }
  if (!m_stop && !x.ok) finish(FitStatus::failed, "the start gives no value of every metric");
  return result();
}

}  // namespace

JointFitResult solve_joint(const JointMetrics& metrics, const JointFitOptions& o) {
  const Eigen::Index n = o.start.size();
  if (o.lo.size() != n || o.hi.size() != n || o.target.size() != o.tolerance.size() || n == 0 ||
      o.target.size() == 0)
    throw std::invalid_argument("solve_joint: options of mismatched sizes");
  if (!(o.lo.array() > 0.0).all() || !(o.lo.array() < o.hi.array()).all() || !o.hi.allFinite())
    throw std::invalid_argument("solve_joint: expected 0 < lo < hi < inf for every parameter");
  if (!(o.tolerance.array() > 0.0).all())
    throw std::invalid_argument("solve_joint: expected positive tolerances");
  return JointSolver(metrics, o).solve();
}

}  // namespace clothbench
