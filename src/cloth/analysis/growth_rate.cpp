#include "cloth/analysis/growth_rate.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace cloth {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

/// The step map in scaled coordinates. A state's free axes become one vector of 2 #F entries:
/// the positions over the length scale L, then the velocities over the speed scale V.
///
/// L is the diagonal of the positions' bounding box (the cloth's size; the largest coordinate,
/// or 1 m, when the particles coincide) and V = L / (steps dt): a velocity perturbation then
/// moves the positions over the map by as much as a position perturbation of the same
/// relative size, so one relative size e suits both halves. In these coordinates the map's
/// Jacobian is S J S^-1 with S = diag(1/L, 1/V) constant, a similarity transform: its
/// eigenvalues are J's whatever L and V are; the scales set only how well the finite
/// differences resolve them.
class ScaledMap {
 public:
  ScaledMap(Simulator& sim, const MapState& s, double dt, int steps, const Matrix3X& free)
      : m_sim(sim), m_s(s), m_dt(dt), m_steps(steps) {
    for (Index p = 0; p < free.cols(); ++p)
      for (int r = 0; r < 3; ++r)
        if (free(r, p) != 0.0) m_axes.push_back({r, p});
    const Vector3 extent = s.x.rowwise().maxCoeff() - s.x.rowwise().minCoeff();
    m_length = extent.norm();
    if (!(m_length > 0.0)) m_length = s.x.cwiseAbs().maxCoeff();
    if (!(m_length > 0.0) || !std::isfinite(m_length)) m_length = 1.0;
    m_speed = m_length / (steps * dt);
  }

  /// Entries of a scaled state, 2 #F.
  Index size() const { return 2 * static_cast<Index>(m_axes.size()); }
  double length() const { return m_length; }  // m
  double speed() const { return m_speed; }    // m/s
  int products() const { return m_products; }
  /// The engine's contact counts at the end of every map evaluated, in order.
  const std::vector<int>& contacts() const { return m_contacts; }

  /// Phi(s + d) in scaled coordinates, d an offset in them (2 #F); counts one product.
  VectorXd operator()(const VectorXd& d) {
    const Index f = static_cast<Index>(m_axes.size());
    Matrix3X x = m_s.x, v = m_s.v;
    for (Index k = 0; k < f; ++k) {
      const auto [r, p] = m_axes[static_cast<size_t>(k)];
      x(r, p) += m_length * d[k];
      v(r, p) += m_speed * d[f + k];
    }
    m_sim.set_state(x, v, m_s.t);
    m_sim.advance(m_dt, m_steps);
    ++m_products;
    m_contacts.push_back(m_sim.contacts());
    // read back the free axes, scaled
    VectorXd out(2 * f);
    const Matrix3X& xe = m_sim.positions();
    const Matrix3X& ve = m_sim.velocities();
    for (Index k = 0; k < f; ++k) {
      const auto [r, p] = m_axes[static_cast<size_t>(k)];
      out[k] = xe(r, p) / m_length;
      out[f + k] = ve(r, p) / m_speed;
    }
    return out;
  }

  /// A scaled vector's position and velocity parts as 3 by #P matrices in metres and metres
  /// per second (held axes 0).
  void unscale(const VectorXd& y, Matrix3X& x, Matrix3X& v) const {
    const Index f = static_cast<Index>(m_axes.size());
    x.setZero(3, m_s.x.cols());
    v.setZero(3, m_s.x.cols());
    for (Index k = 0; k < f; ++k) {
      const auto [r, p] = m_axes[static_cast<size_t>(k)];
      x(r, p) = m_length * y[k];
      v(r, p) = m_speed * y[f + k];
    }
  }

 private:
  struct Axis {
    int row;
    Index particle;
  };
  Simulator& m_sim;
  const MapState& m_s;
  double m_dt;
  int m_steps;
  std::vector<Axis> m_axes;  // the free axes, particle by particle
  double m_length = 1, m_speed = 1;
  int m_products = 0;
  std::vector<int> m_contacts;
};

/// The refusals of the header.
void check_arguments(const Simulator& sim, const MapState& s, double dt, int steps,
                     const Matrix3X& free, const GrowthOptions& o) {
  if (!(o.perturbation >= kMinPerturbation))
    throw std::invalid_argument("growth: perturbation " + std::to_string(o.perturbation) +
                                " is below the smallest accepted, 1e-12");
  if (o.max_iterations < 1) throw std::invalid_argument("growth: max_iterations must be >= 1");
  if (steps < 1) throw std::invalid_argument("growth: steps must be at least 1");
  if (!(dt > 0.0)) throw std::invalid_argument("growth: dt must be positive");
  const Index n = s.x.cols();
  if (s.v.cols() != n || free.cols() != n)
    throw std::invalid_argument("growth: state and free axes must have the same particles");
  if (free.isZero()) throw std::invalid_argument("growth: no free axis to perturb");
  if (!sim.can_set_state()) throw std::logic_error("growth: the engine cannot set its state");
}

/// k orthonormal columns of 2 #F entries from a fixed seed, the same on every machine.
MatrixXd start_vectors(Index n, Index k) {
  std::mt19937_64 bits(20261127u);
  MatrixXd q(n, k);
  // uniform in [-1, 1) from the top 53 bits (no library distribution, whose output may differ)
  for (Index j = 0; j < k; ++j)
    for (Index i = 0; i < n; ++i) q(i, j) = static_cast<double>(bits() >> 11) * 0x1.0p-52 - 1.0;
  Eigen::HouseholderQR<MatrixXd> qr(q);
  return qr.householderQ() * MatrixXd::Identity(n, k);
}

/// The Ritz value of largest modulus of the projected matrix h (k by k) and its eigenvector;
/// of a complex pair the one with positive imaginary part.
std::complex<double> dominant(const MatrixXd& h, Eigen::VectorXcd* vector) {
  Eigen::EigenSolver<MatrixXd> es(h, vector != nullptr);
  const Eigen::VectorXcd& values = es.eigenvalues();
  Index best = 0;
  for (Index i = 1; i < values.size(); ++i) {
    const double a = std::abs(values[i]), b = std::abs(values[best]);
    if (a > b * (1 + 1e-12) || (a >= b * (1 - 1e-12) && values[i].imag() > values[best].imag()))
      best = i;
  }
  if (vector) *vector = es.eigenvectors().col(best);
  return values[best];
}

/// The residual |J y - theta y| of the Ritz pair with eigenvector z (y = Q z / |z|) of the
/// m by m Hessenberg matrix h: h(m, m-1) |z_m| / |z|, which needs no product.
double ritz_residual(const MatrixXd& h, Index m, const Eigen::VectorXcd& z) {
  return h(m, m - 1) * std::abs(z[m - 1]) / z.norm();
}

/// The dominant Ritz vector q z mapped back to a 3 by #P mode, normalised so that its
/// largest position entry (velocity entry, when the positions are all zero) is 1.
void write_mode(const ScaledMap& map, const MatrixXd& q, const Eigen::VectorXcd& z,
                GrowthEstimate& out) {
  const Eigen::VectorXcd y = q.cast<std::complex<double>>() * z;
  const Index f = y.size() / 2;
  Matrix3X xr, vr, xi, vi;
  map.unscale(y.real(), xr, vr);
  map.unscale(y.imag(), xi, vi);
  // the largest entry in modulus, in physical units
  const Matrix3X xm = (xr.array().square() + xi.array().square()).sqrt().matrix();
  const Matrix3X vm = (vr.array().square() + vi.array().square()).sqrt().matrix();
  const bool by_velocity = !(xm.maxCoeff() > 0.0);
  Index r = 0, c = 0;
  (by_velocity ? vm : xm).maxCoeff(&r, &c);
  const std::complex<double> pivot = by_velocity ? std::complex<double>(vr(r, c), vi(r, c))
                                                 : std::complex<double>(xr(r, c), xi(r, c));
  if (std::abs(pivot) == 0.0 || f == 0) return;
  // y / pivot, real part: (a + bi) / p = ((a + bi) conj(p)) / |p|^2
  const std::complex<double> s = std::conj(pivot) / std::norm(pivot);
  out.mode = s.real() * xr - s.imag() * xi;
  out.mode_velocity = s.real() * vr - s.imag() * vi;
}

/// Compares the forward differences w (2 #F by k, J q) with backward ones on the same vectors
/// q, and the contact counts of the maps from the from-th on (those along q) with the base
/// map's. Only the directions that matter are asked: a contact that flips under the Krylov
/// vectors' perturbation of every particle, far from where the mode lives, does not make the
/// mode's growth ill-defined.
void check_smoothness(ScaledMap& map, const VectorXd& base, const MatrixXd& q, const MatrixXd& w,
                      double e, double tol, size_t from, GrowthEstimate& out) {
  double worst = 0.0;
  for (Index j = 0; j < q.cols(); ++j) {
    const VectorXd backward = (base - map(-e * q.col(j))) / e;
    const double scale = std::max(w.col(j).norm(), backward.norm());
    const double gap = (w.col(j) - backward).norm();
    if (!std::isfinite(gap)) worst = INFINITY;
    if (scale > 0.0) worst = std::max(worst, gap / scale);
  }
  if (!(worst <= tol)) {
    out.smooth = false;
    out.nonsmooth_reason = "forward and backward differences differ by " +
                           std::to_string(static_cast<int>(std::ceil(100 * worst))) + "%";
  }
  // a contact switching on or off makes the map's derivative jump at the state
  const std::vector<int>& counts = map.contacts();
  for (size_t i = from; i < counts.size(); ++i)
    if (const int c = counts[i]; counts.front() >= 0 && c != counts.front()) {
      out.smooth = false;
      out.nonsmooth_reason = "contacts change under the perturbation (" +
                             std::to_string(counts.front()) + " in the base map and " +
                             std::to_string(c) + " in a perturbed one)";
      return;
    }
}

}  // namespace

int decided_side(std::complex<double> theta, double residual, double below, double above) {
  const double r = std::abs(theta), delta = std::sqrt(residual);
  if (r + delta < below) return -1;
  if (r - delta > above) return 1;
  return 0;
}

GrowthEstimate estimate_growth(Simulator& sim, const MapState& s, double dt, int steps,
                               const Matrix3X& free, const GrowthOptions& o) {
  check_arguments(sim, s, dt, steps, free, o);
  ScaledMap map(sim, s, dt, steps, free);
  const Index n = map.size();
  const Index m_max = std::min<Index>(o.max_iterations, n);
  const double e = o.perturbation;
  GrowthEstimate out;
  // the base map, then Arnoldi: each forward difference J q_m, orthogonalised (twice) against
  // the Krylov basis so far, extends the Hessenberg matrix whose eigenvalues (Ritz values)
  // approach J's outermost eigenvalues, complex pairs included
  const VectorXd base = map(VectorXd::Zero(n));
  MatrixXd q = MatrixXd::Zero(n, m_max + 1), h = MatrixXd::Zero(m_max + 1, m_max);
  q.col(0) = start_vectors(n, 1);
  bool finite = base.allFinite();
  Eigen::VectorXcd z;
  Index m = 0;
  int side = 0, agreeing = 0;  // the side decided at the last checks, and how many in a row
  while (finite && m < m_max) {
    VectorXd w = (map(e * q.col(m)) - base) / e;
    finite = w.allFinite();
    if (!finite) break;
    for (int pass = 0; pass < 2; ++pass)
      for (Index i = 0; i <= m; ++i) {
        const double c = q.col(i).dot(w);
        h(i, m) += c;
        w -= c * q.col(i);
      }
    h(m + 1, m) = w.norm();
    ++m;
    out.iterations = static_cast<int>(m);
    const bool invariant = h(m, m - 1) <= 1e-14 * h.topLeftCorner(m, m).norm();
    if (!invariant) q.col(m) = w / h(m, m - 1);
    // the Ritz pair of largest modulus and its residual |J y - theta y| = h(m, m-1) |z_m|,
    // which needs no product: converged when it is below rel_tol |theta| (for a non-normal J
    // a small Ritz value error needs a small residual, not a settled value)
    if (m < m_max && !invariant && m > 8 && m % 4 != 0) continue;
    out.eigenvalue = dominant(h.topLeftCorner(m, m), &z);
    const double residual = ritz_residual(h, m, z);
    if (invariant || (m >= 2 && residual <= o.rel_tol * std::abs(out.eigenvalue))) {
      out.converged = true;
      break;
    }
    // a caller that needs only a side of a threshold: stop once it is decided and stays so
    const int now = decided_side(out.eigenvalue, residual, o.decide_below, o.decide_above);
    agreeing = now != 0 && now == side ? agreeing + 1 : 1;
    side = now;
    if (m >= 2 && side != 0 && agreeing >= o.decide_checks &&
        residual <= o.decide_residual * std::abs(out.eigenvalue)) {
      out.decided = side;
      break;
    }
  }
  // a map that overflowed (or a state that was not finite) grows without a measurable bound
  if (!finite) {
    out.rho = out.rate = INFINITY;
    out.converged = false;
    out.products = map.products();
    return out;
  }
  out.eigenvalue = dominant(h.topLeftCorner(m, m), &z);
  if (m > 0) out.residual = ritz_residual(h, m, z);
  out.rho = std::abs(out.eigenvalue);
  out.rate = std::log(out.rho) / (steps * dt);
  write_mode(map, q.leftCols(m), z, out);
  // smoothness along the mode's real direction: one forward and one backward difference
  VectorXd y = (q.leftCols(m) * z.real()).normalized();
  if (!y.allFinite() || y.norm() == 0) y = q.col(0);
  const size_t from = map.contacts().size();
  const MatrixXd forward = (map(e * y) - base) / e;
  check_smoothness(map, base, y, forward, e, o.nonsmooth_tol, from, out);
  out.products = map.products();
  return out;
}

}  // namespace cloth
