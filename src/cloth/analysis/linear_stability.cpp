#include "cloth/analysis/linear_stability.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "cloth/forces/spring_jacobians.hpp"

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
    case Integrator::imex_euler:
      break;  // not a one-step map of (x, v) as one system: see radius()
    case Integrator::xpbd:
    case Integrator::projective:
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

// spectral radius of one step of size h on the mode q'' + a q' + omega^2 q = 0
double radius(Integrator i, double h, double omega, double a) {
  if (i == Integrator::symplectic_euler) {
    // v1 = (1 - h a) v0 - h omega^2 x0, x1 = x0 + h v1: the step matrix has trace 2 - 2 e
    // and determinant 1 - h a, e = (h a + h^2 omega^2) / 2, so its eigenvalues are
    // 1 - e +- sqrt(e^2 - h^2 omega^2) (the discriminant written without cancellation)
    const double e = 0.5 * (h * a + h * h * omega * omega);
    const cd root = std::sqrt(cd(e * e - h * h * omega * omega, 0.0));
    return std::max(std::abs(1.0 - e + root), std::abs(1.0 - e - root));
  }
  if (i == Integrator::imex_euler) {
    // v1 = (v0 - h omega^2 x0) / (1 + h a), x1 = x0 + h v1: the step matrix has determinant
    // d = 1 / (1 + h a) and trace (2 + u - w) d, u = h a, w = h^2 omega^2; its discriminant,
    // written without cancellation, is ((u - w)^2 - 4 w) d^2 / 4
    const double u = h * a, w = h * h * omega * omega, d = 1.0 / (1.0 + u);
    const double disc = (u - w) * (u - w) - 4.0 * w;
    if (disc < 0.0) return std::sqrt(d);  // a complex pair of modulus sqrt(det)
    const double b = 2.0 + u - w;
    const double q = b + std::copysign(std::sqrt(disc), b);  // the larger root, no cancellation
    const double big = std::abs(q) * 0.5 * d;
    return std::max(big, big > 0.0 ? d / big : 0.0);
  }
  // roots of lambda^2 + a lambda + omega^2 = 0
  const cd disc = std::sqrt(cd(a * a - 4.0 * omega * omega, 0.0));
  const cd l1 = 0.5 * (-a + disc), l2 = 0.5 * (-a - disc);
  return std::max(std::abs(amplification(i, h * l1)), std::abs(amplification(i, h * l2)));
}

constexpr double kSlack = 1e-12;  // round-off in |R| for modes right on the boundary

// the modes a spectrum's limits are checked on: its dense modes, or the grid over
// [0, omega_max] with a = beta omega^2 + gamma; the rigid mode omega = 0 always
std::vector<DampedMode> checked_modes(const LinearSpectrum& s) {
  std::vector<DampedMode> out = s.modes;
  if (out.empty())
    for (double w : mode_grid(s.omega_max)) out.push_back({w, s.beta * w * w + s.gamma});
  out.push_back({0.0, s.gamma});
  return out;
}

bool all_modes_stable(Integrator i, double h, const std::vector<DampedMode>& modes) {
  for (const DampedMode& m : modes)
    if (radius(i, h, m.omega, m.a) > 1.0 + kSlack) return false;
  return true;
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

// the dense modal analysis of the file comment: fills s.modes, s.omega_max, s.beta, s.method
void dense_modes(const Model& model, const SpringLinearization& lin, LinearSpectrum& s) {
  // the free DOFs, as flat indices 3 p + r into a 3 by #P matrix
  const Eigen::Index n = model.particle_count();
  std::vector<Eigen::Index> dof;
  for (Eigen::Index p = 0; p < n; ++p)
    for (int r = 0; r < 3; ++r)
      if (model.free(r, p) > 0) dof.push_back(3 * p + r);
  const Eigen::Index N = static_cast<Eigen::Index>(dof.size());
  if (N == 0) return;

  // mass-weighted K and D (springs and drag): M^-1/2 K M^-1/2 is symmetric for any masses
  Eigen::MatrixXd K(N, N), D(N, N);
  Eigen::VectorXd w(N);  // M^-1/2 per DOF
  for (Eigen::Index i = 0; i < N; ++i) w[i] = std::sqrt(model.inv_mass[dof[size_t(i)] / 3]);
  Matrix3X u = Matrix3X::Zero(3, n), y(3, n), buf(3, n);
  for (Eigen::Index j = 0; j < N; ++j) {
    u.data()[dof[size_t(j)]] = 1.0;
    y.setZero();
    add_jacobian_product(model.springs, lin, u, 1.0, 0.0, y, buf);
    for (Eigen::Index i = 0; i < N; ++i) K(i, j) = w[i] * y.data()[dof[size_t(i)]] * w[j];
    y.setZero();
    add_jacobian_product(model.springs, lin, u, 0.0, 1.0, y, buf);
    for (Eigen::Index i = 0; i < N; ++i) D(i, j) = w[i] * y.data()[dof[size_t(i)]] * w[j];
    D(j, j) -= model.air_drag * w[j] * w[j];
    u.data()[dof[size_t(j)]] = 0.0;
  }

  // the undamped modes: -K phi = omega^2 phi, ascending
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(-0.5 * (K + K.transpose()));
  const Eigen::VectorXd& w2 = es.eigenvalues();
  const Eigen::MatrixXd& phi = es.eigenvectors();
  const Eigen::MatrixXd dphi = D * phi;
  s.omega_max = std::sqrt(std::max(0.0, w2[N - 1]));
  s.beta = w2[N - 1] > 0 ? -phi.col(N - 1).dot(dphi.col(N - 1)) / w2[N - 1] : 0.0;

  // the top modes coupled through D: q'' = -Omega^2 q + Phi^T D Phi q', as a first-order
  // system of twice their number. Modes of zero frequency stay out: their double root 0 is
  // defective, which an eigensolver returns with a spurious real part of order sqrt(eps),
  // and at rest D vanishes on them as K does (every damper sits on a spring)
  const Eigen::Index moving = (w2.array() > 1e-9 * w2[N - 1]).count();
  const Eigen::Index top = std::min<Eigen::Index>(moving, std::max<Eigen::Index>(200, N / 3));
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * top, 2 * top);
  A.topRightCorner(top, top).setIdentity();
  A.bottomLeftCorner(top, top).diagonal() = -w2.tail(top).cwiseMax(0.0);
  A.bottomRightCorner(top, top) = phi.rightCols(top).transpose() * dphi.rightCols(top);
  const Eigen::EigenSolver<Eigen::MatrixXd> ev = top > 0
                                                     ? Eigen::EigenSolver<Eigen::MatrixXd>(A, false)
                                                     : Eigen::EigenSolver<Eigen::MatrixXd>();
  // each complex pair is the oscillator with those roots; real roots are paired fastest with
  // slowest (the pairing matters to symplectic Euler alone: the others see each root as is)
  std::vector<double> real;
  for (Eigen::Index j = 0; top > 0 && j < 2 * top; ++j) {
    const cd l = ev.eigenvalues()[j];
    if (l.imag() > 0)
      s.modes.push_back({std::abs(l), -2.0 * l.real()});
    else if (l.imag() == 0)
      real.push_back(l.real());
  }
  std::sort(real.begin(), real.end());
  for (size_t a = 0, b = real.size(); a + 1 < b; ++a, --b) {
    const double l1 = real[a], l2 = real[b - 1];
    s.modes.push_back({std::sqrt(std::max(0.0, l1 * l2)), -(l1 + l2)});
  }
  // the lower modes with their own damping
  for (Eigen::Index j = 0; j < N - top; ++j)
    s.modes.push_back({std::sqrt(std::max(0.0, w2[j])), -phi.col(j).dot(dphi.col(j))});
  // symplectic Euler: a smaller top block, coupled, and the rest with their own damping
  const Eigen::Index se_top = std::min<Eigen::Index>(moving, kSymplecticCoupled);
  s.coupled_omega2 = w2.tail(se_top).cwiseMax(0.0);
  s.coupled_damping = phi.rightCols(se_top).transpose() * dphi.rightCols(se_top);
  for (Eigen::Index j = 0; j < N - se_top; ++j)
    s.uncoupled.push_back({std::sqrt(std::max(0.0, w2[j])), -phi.col(j).dot(dphi.col(j))});
  s.method = "damping not proportional to stiffness: " + std::to_string(N) +
             " modes from a dense analysis with the top " + std::to_string(top) +
             " coupled through the damping";
}

// symplectic Euler on the coupled block: its step's eigenvalues are 1 + h s for the
// eigenvalues s of this first-order matrix (damping M^-1 D + h M^-1 K, see the file comment)
Eigen::MatrixXd symplectic_block(const LinearSpectrum& s, double h) {
  const Eigen::Index k = s.coupled_omega2.size();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * k, 2 * k);
  A.topRightCorner(k, k).setIdentity();
  A.bottomLeftCorner(k, k).diagonal() = -s.coupled_omega2;
  A.bottomRightCorner(k, k) = s.coupled_damping;
  A.bottomRightCorner(k, k).diagonal() -= h * s.coupled_omega2;
  return A;
}

Eigen::VectorXcd symplectic_block_eigenvalues(const LinearSpectrum& s, double h) {
  const Eigen::EigenSolver<Eigen::MatrixXd> ev(symplectic_block(s, h), false);
  return (1.0 + h * ev.eigenvalues().array()).matrix();
}

bool symplectic_coupled_stable(const LinearSpectrum& s, double h) {
  if (!all_modes_stable(Integrator::symplectic_euler, h, s.uncoupled)) return false;
  if (radius(Integrator::symplectic_euler, h, 0.0, s.gamma) > 1.0 + kSlack) return false;
  return symplectic_block_eigenvalues(s, h).cwiseAbs().maxCoeff() <= 1.0 + kSlack;
}

// symplectic Euler's first failure with the coupled block: each check is an eigenproblem, so
// the march starts from half the limit of the modes taken one by one
double symplectic_coupled_limit(const LinearSpectrum& s) {
  std::vector<DampedMode> one_by_one = s.uncoupled;
  for (Eigen::Index j = 0; j < s.coupled_omega2.size(); ++j)
    one_by_one.push_back({std::sqrt(s.coupled_omega2[j]), -s.coupled_damping(j, j)});
  one_by_one.push_back({0.0, s.gamma});
  double lo = 1e-9 / std::max(1.0, s.omega_max), hi = lo;
  while (all_modes_stable(Integrator::symplectic_euler, hi, one_by_one) && hi < 1e3) hi *= 1.01;
  lo = 0.5 * hi;
  for (int k = 0; k < 60 && !symplectic_coupled_stable(s, lo); ++k) lo *= 0.5;
  // march up in 1% steps to the first unstable h, then bisect
  hi = lo;
  while (symplectic_coupled_stable(s, hi)) {
    lo = hi;
    hi *= 1.01;
    if (hi > 1e3) return std::numeric_limits<double>::infinity();
  }
  for (int it = 0; it < 60 && (hi - lo) > 1e-10 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (symplectic_coupled_stable(s, mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

bool mode_stable(Integrator i, double h, double omega, double beta, double gamma) {
  return mode_radius(i, h, omega, beta, gamma) <= 1.0 + kSlack;
}

double mode_radius(Integrator i, double h, double omega, double beta, double gamma) {
  return radius(i, h, omega, beta * omega * omega + gamma);
}

LinearSpectrum linear_spectrum(const Model& model, int max_steps, int dense_max_dofs) {
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
  const double top = es.eigenvalues().maxCoeff();
  s.omega_max = std::sqrt(std::max(0.0, top));
  // modal damping: exact c / k when every spring kind has the same stiffness
  double k0 = -1.0;
  bool same = true;
  for_each_spring(model.springs, [&](int, int, size_t g, int slot) {
    const double ks = model.springs.stiffness(g, slot);
    if (k0 < 0) k0 = ks;
    same = same && ks == k0;
  });
  s.method = "damping proportional to stiffness: exact";
  if (k0 <= 0) return s;
  if (same) {
    s.beta = model.springs.damping / k0;
    return s;
  }
  s.exact = false;
  if (dofs <= dense_max_dofs) {
    dense_modes(model, lin, s);
    return s;
  }
  // otherwise the Rayleigh quotient of the damping on the top Ritz vector
  s.method =
      "damping not proportional to stiffness: modal damping approximated by the top "
      "mode's";
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
  // backward Euler, and the two position solvers whose springs act implicitly in position,
  // have no linear limit
  if (i == Integrator::implicit_euler || i == Integrator::xpbd || i == Integrator::projective ||
      s.omega_max <= 0)
    return std::numeric_limits<double>::infinity();
  if (i == Integrator::symplectic_euler && s.coupled_omega2.size() > 0)
    return symplectic_coupled_limit(s);
  const std::vector<DampedMode> modes = checked_modes(s);
  // march up in 1% steps to the first unstable h, then bisect
  double lo = 1e-9 / std::max(1.0, s.omega_max), hi = lo;
  while (all_modes_stable(i, hi, modes)) {
    lo = hi;
    hi *= 1.01;
    if (hi > 1e3) return std::numeric_limits<double>::infinity();
  }
  for (int it = 0; it < 60 && (hi - lo) > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (all_modes_stable(i, mid, modes) ? lo : hi) = mid;
  }
  return lo;
}

std::string limiting_mode(Integrator i, const LinearSpectrum& s) {
  return limiting_mode(i, s, predicted_stable_dt(i, s));
}

std::string limiting_mode(Integrator i, const LinearSpectrum& s, double h) {
  if (!std::isfinite(h)) return "none (unconditionally stable)";
  // the mode that grows fastest just past the limit
  const double h_fail = h * 1.001;
  DampedMode worst;
  double worst_radius = 0.0;
  const bool coupled = i == Integrator::symplectic_euler && s.coupled_omega2.size() > 0;
  for (const DampedMode& mode : coupled ? s.uncoupled : checked_modes(s)) {
    const double r = radius(i, h_fail, mode.omega, mode.a);
    if (r > worst_radius) {
      worst_radius = r;
      worst = mode;
    }
  }
  if (coupled) {
    // the block's fastest-growing eigenvector, named by the mode it moves most
    const Eigen::EigenSolver<Eigen::MatrixXd> ev(symplectic_block(s, h_fail));
    Eigen::Index j = 0, m = 0;
    if ((1.0 + h_fail * ev.eigenvalues().array()).abs().maxCoeff(&j) > worst_radius) {
      ev.eigenvectors().col(j).head(s.coupled_omega2.size()).cwiseAbs().maxCoeff(&m);
      worst = {std::sqrt(s.coupled_omega2[m]), -s.coupled_damping(m, m)};
    }
  }
  std::ostringstream o;
  o.precision(4);
  o << "omega " << worst.omega << " rad/s ("
    << (worst.a >= 2 * worst.omega ? "overdamped" : "oscillatory") << ")";
  return o.str();
}

}  // namespace cloth
