#include "cloth/linear_stability.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "cloth/spring_jacobians.hpp"

namespace cloth {

namespace {

using cd = std::complex<double>;

// amplification factor R(z) of the methods that treat (x, v) as one first-order system
cd amplification(Integrator i, cd z) {
  switch (i) {
    case Integrator::explicit_euler:
      return 1.0 + z;
    case Integrator::picard_implicit:
      return 1.0 + z + z * z;
    case Integrator::midpoint:
      return 1.0 + z + 0.5 * z * z;
    case Integrator::rk4:
      return 1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0;
    case Integrator::implicit_euler:
      return 1.0 / (1.0 - z);
    case Integrator::symplectic_euler:
      break;
  }
  return 0.0;
}

// the stable set of h for one method: grid of modes over [0, omega_max], denser at the top
std::vector<double> mode_grid(double omega_max) {
  std::vector<double> w;
  const int n = 400;
  for (int k = 1; k <= n; ++k) w.push_back(omega_max * std::sqrt(double(k) / n));
  for (int k = 1; k <= n; ++k) w.push_back(omega_max * double(k) / n);
  return w;
}

bool all_modes_stable(Integrator i, double h, const LinearSpectrum& s) {
  for (double w : mode_grid(s.omega_max))
    if (!mode_stable(i, h, w, s.beta, s.gamma)) return false;
  return mode_stable(i, h, 0.0, s.beta, s.gamma);
}

// y = -M^-1 K u on the free DOFs (symmetric positive semidefinite for uniform mass in the
// mass-weighted inner product; the cloth's masses are uniform)
void apply_stiffness(const Model& m, const SpringLinearization& lin, const Matrix3X& u, Matrix3X& y,
                     Matrix3X& buf) {
  y.setZero();
  add_jacobian_product(m.springs, lin, u, -1.0, 0.0, y, buf);
  for (int r = 0; r < 3; ++r) y.row(r) = y.row(r).cwiseProduct(m.inv_mass.transpose());
  y.array() *= m.free.array();
}

}  // namespace

bool mode_stable(Integrator i, double h, double omega, double beta, double gamma) {
  constexpr double kSlack = 1e-12;  // round-off in |R| for modes right on the boundary
  return mode_radius(i, h, omega, beta, gamma) <= 1.0 + kSlack;
}

double mode_radius(Integrator i, double h, double omega, double beta, double gamma) {
  const double a = beta * omega * omega + gamma;  // q'' + a q' + omega^2 q = 0
  if (i == Integrator::symplectic_euler) {
    // v1 = (1 - h a) v0 - h omega^2 x0, x1 = x0 + h v1
    Eigen::Matrix2d S;
    S << 1.0 - h * h * omega * omega, h * (1.0 - h * a), -h * omega * omega, 1.0 - h * a;
    const Eigen::Vector2cd ev = S.eigenvalues();
    return std::max(std::abs(ev[0]), std::abs(ev[1]));
  }
  // roots of lambda^2 + a lambda + omega^2 = 0
  const cd disc = std::sqrt(cd(a * a - 4.0 * omega * omega, 0.0));
  const cd l1 = 0.5 * (-a + disc), l2 = 0.5 * (-a - disc);
  return std::max(std::abs(amplification(i, h * l1)), std::abs(amplification(i, h * l2)));
}

LinearSpectrum linear_spectrum(const Model& model, int max_steps) {
  LinearSpectrum s;
  const Eigen::Index n = model.particle_count();
  const double m = model.mass.mean();
  s.gamma = model.air_drag / m;
  SpringLinearization lin;
  linearize_springs(model.springs, model.x0, false, lin);
  // Lanczos on -M^-1 K restricted to the free DOFs (uniform masses make it symmetric)
  const int dofs = static_cast<int>(model.free.sum());
  const int steps = std::max(1, std::min(max_steps, dofs));
  std::vector<Matrix3X> Q;
  Eigen::VectorXd alpha(steps), beta_l(steps);
  Matrix3X q(3, n), w(3, n), buf(3, n);
  // deterministic start: a smooth-plus-rough pattern touching every free DOF
  for (Eigen::Index p = 0; p < n; ++p)
    for (int r = 0; r < 3; ++r) q(r, p) = 1.0 + 0.5 * std::sin(1.7 * p + 2.3 * r);
  q.array() *= model.free.array();
  q /= q.norm();
  int k = 0;
  for (; k < steps; ++k) {
    Q.push_back(q);
    apply_stiffness(model, lin, q, w, buf);
    alpha[k] = (w.array() * q.array()).sum();
    // full reorthogonalisation keeps the Ritz values clean of ghosts
    for (const Matrix3X& qj : Q) w -= (w.array() * qj.array()).sum() * qj;
    for (const Matrix3X& qj : Q) w -= (w.array() * qj.array()).sum() * qj;
    const double b = w.norm();
    beta_l[k] = b;
    if (b < 1e-12 * std::max(1.0, std::abs(alpha[k]))) {
      ++k;
      break;
    }
    q = w / b;
  }
  s.lanczos_steps = k;
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(k, k);
  for (int j = 0; j < k; ++j) {
    T(j, j) = alpha[j];
    if (j + 1 < k) T(j, j + 1) = T(j + 1, j) = beta_l[j];
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(T);
  const double top = es.eigenvalues().maxCoeff(), low = es.eigenvalues().minCoeff();
  s.omega_max = std::sqrt(std::max(0.0, top));
  s.omega_min = std::sqrt(std::max(0.0, low));
  // modal damping: exact c / k when every spring kind has the same stiffness
  double k0 = -1.0;
  bool same = true;
  for (const SpringFamily& f : model.springs.families) {
    if (k0 < 0) k0 = f.stiffness;
    same = same && f.stiffness == k0;
  }
  if (k0 <= 0) return s;
  if (same) {
    s.beta = model.springs.damping / k0;
    return s;
  }
  // otherwise the Rayleigh quotient of the damping on the top Ritz vector
  s.exact = false;
  const Eigen::VectorXd y = es.eigenvectors().col(static_cast<Eigen::Index>(
      std::max_element(es.eigenvalues().data(), es.eigenvalues().data() + k) -
      es.eigenvalues().data()));
  Matrix3X phi = Matrix3X::Zero(3, n);
  for (int j = 0; j < k; ++j) phi += y[j] * Q[static_cast<size_t>(j)];
  Matrix3X dphi = Matrix3X::Zero(3, n);
  add_jacobian_product(model.springs, lin, phi, 0.0, -1.0, dphi, buf);
  dphi.array() *= model.free.array();
  const double damping_q = (dphi.array() * phi.array()).sum() / m;  // -phi^T D phi / m
  s.beta = top > 0 ? damping_q / top : 0.0;
  return s;
}

double predicted_stable_dt(Integrator i, const LinearSpectrum& s) {
  if (i == Integrator::implicit_euler || s.omega_max <= 0)
    return std::numeric_limits<double>::infinity();
  // march up in 1% steps to the first unstable h, then bisect
  double lo = 1e-9 / std::max(1.0, s.omega_max), hi = lo;
  while (all_modes_stable(i, hi, s)) {
    lo = hi;
    hi *= 1.01;
    if (hi > 1e3) return std::numeric_limits<double>::infinity();
  }
  for (int it = 0; it < 60 && (hi - lo) > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (all_modes_stable(i, mid, s) ? lo : hi) = mid;
  }
  return lo;
}

std::string limiting_mode(Integrator i, const LinearSpectrum& s) {
  const double h = predicted_stable_dt(i, s);
  if (!std::isfinite(h)) return "none (unconditionally stable)";
  // the mode that grows fastest just past the limit
  const double h_fail = h * 1.001;
  double worst = 0.0, worst_radius = 0.0;
  for (double w : mode_grid(s.omega_max)) {
    const double r = mode_radius(i, h_fail, w, s.beta, s.gamma);
    if (r > worst_radius) {
      worst_radius = r;
      worst = w;
    }
  }
  std::ostringstream o;
  o.precision(4);
  const double a = s.beta * worst * worst + s.gamma;
  o << "omega " << worst << " rad/s (" << (a >= 2 * worst ? "overdamped" : "oscillatory") << ")";
  return o.str();
}

}  // namespace cloth
