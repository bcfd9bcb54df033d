#include "cloth/integrators/implicit_euler.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cloth/forces/spring_forces.hpp"

namespace cloth {

namespace {

// armijo's sufficient-decrease constant and the line search's halvings
constexpr double kArmijo = 1e-4;
constexpr int kMaxHalvings = 30;

// trust region (Nocedal and Wright, Numerical Optimization, algorithm 4.1): a step is taken when
// Phi falls by at least kAcceptRatio of the model's predicted decrease; the radius shrinks to
// kShrink times the step below kShrinkRatio and doubles when a step on the edge reaches
// kGrowRatio
constexpr double kAcceptRatio = 1e-4;
constexpr double kShrinkRatio = 0.25;
constexpr double kGrowRatio = 0.75;
constexpr double kShrink = 0.25;
// a predicted decrease this small relative to |Phi| is below Phi's rounding: any fall is taken
constexpr double kRoundoff = 1e-13;

}  // namespace

LinearSolver resolved_linear_solver(LinearSolver s, int particles, bool grid) {
  // the coarse grid's setup and solves cost more than they save below about 40 per edge;
  // ldlt was never the fastest (README, "Large steps")
  if (s != LinearSolver::automatic) return s;
  return grid && particles >= kTwoLevelMinParticles ? LinearSolver::two_level_cg
                                                    : LinearSolver::block_jacobi_cg;
}

ImplicitEulerNewton::ImplicitEulerNewton(const Model& m, const SolverOptions& o)
    : ImplicitEulerNewton(
          m, o,
          resolved_linear_solver(o.linear_solver, m.particle_count(), m.springs.list.empty())) {}

ImplicitEulerNewton::ImplicitEulerNewton(const Model& m, const SolverOptions& o,
                                         LinearSolver solver)
    : m_matrix(m, solver == LinearSolver::ldlt),
      m_solver(m, solver),
      m_barrier(m),
      m_direct(solver == LinearSolver::ldlt) {
  if (m_direct && o.newton == NewtonMethod::trust_region)
    throw std::invalid_argument(
        "newton = \"trust-region\" needs a conjugate-gradient linear_solver, not ldlt");
  const Eigen::Index n = m.particle_count();
  for (Matrix3X* a :
       {&m_x0, &m_v0, &m_v, &m_x, &m_trial, &m_dv, &m_force, &m_damp, &m_zero, &m_buf, &m_rhs})
    a->setZero(3, n);
  m_history.reserve(static_cast<size_t>(o.newton_iterations) + 1);
  m_residuals.reserve(static_cast<size_t>(o.newton_iterations) + 1);
  // the trust region's mass norm, zero on held axes
  m_weights = m.free;
  for (int r = 0; r < 3; ++r) m_weights.row(r) = m_weights.row(r).cwiseProduct(m.mass.transpose());
}

double ImplicitEulerNewton::objective(const Model& m, double h, const Matrix3X& v) {
  m_x = m_x0 + h * v;
  // inertia 1/2 |v - v0 - h g|_M^2 over free axes (held axes add a constant)
  double inertia = 0.0;
  for (int r = 0; r < 3; ++r)
    inertia += ((v.row(r) - m_v0.row(r)).array() - h * m.gravity[r])
                   .square()
                   .matrix()
                   .cwiseProduct(m.free.row(r))
                   .dot(m.mass.transpose());
  // dampers' Rayleigh potential: v . D0 v = -c sum (d0 . (v_q - v_p))^2
  m_damp.setZero();
  add_jacobian_product(m.springs, m_lin0, v, 0.0, 1.0, m_damp, m_buf);
  // drag's potential: c |v - wind|^2 less the constant c |wind|^2
  const double rayleigh = -v.cwiseProduct(m_damp).sum() + m.air_drag * v.squaredNorm() -
                          2.0 * m.air_drag * m.wind.dot(v.rowwise().sum());
  const double contact =
      m_use_barrier ? m_barrier.energy(m, m_t_end, m_x) + m_friction.energy(v) : 0.0;
  return 0.5 * inertia + elastic_energy(m.springs, m_x) + 0.5 * h * rayleigh + contact;
}

double ImplicitEulerNewton::residual(const Model& m, double h, const Matrix3X& v) {
  m_x = m_x0 + h * v;
  // f = elastic force at x + frozen-direction damping + drag + gravity
  m_force.setZero();
  add_spring_forces(m.springs, m_x, m_zero, m_force, m_buf);
  add_jacobian_product(m.springs, m_lin0, v, 0.0, 1.0, m_force, m_buf);
  m.add_drag(v, m_force);
  for (int r = 0; r < 3; ++r) m_force.row(r) += m.gravity[r] * m.mass.transpose();
  if (m_use_barrier) {
    m_barrier.contacts(m, m_t_end, m_x, m_barrier_contacts, h);
    ColliderBarrier::add_forces(m_barrier_contacts, m_force);
    m_friction.add_forces(v, m_force);
  }
  // rhs = -grad Phi = h f - M (v - v0), zero on held axes
  for (int r = 0; r < 3; ++r)
    m_rhs.row(r) = h * m_force.row(r) - (v.row(r) - m_v0.row(r)).cwiseProduct(m.mass.transpose());
  m_rhs = (m.free.array() > 0.0).select(m_rhs, 0.0);
  // a contact's normal part is the constraint's impulse, -(n . rhs) along n (N s)
  m_impulse.resize(m_contacts.size());
  for (size_t k = 0; k < m_contacts.size(); ++k) {
    const ContactConstraint& c = m_contacts[k];
    m_impulse[k] = -c.normal.dot(m_rhs.col(c.particle));
  }
  remove_normal_parts(m_contacts, m_rhs);
  double worst = 0.0;
  for (int r = 0; r < 3; ++r)
    worst =
        std::max(worst, m_rhs.row(r).cwiseProduct(m.inv_mass.transpose()).cwiseAbs().maxCoeff());
  return worst;
}

bool ImplicitEulerNewton::line_search(const Model& m, double h, double slope, Counters& counters) {
  // backtracking from the full Newton step until Armijo's condition holds on Phi
  double alpha = 1.0;
  for (int i = 0; i < kMaxHalvings; ++i, alpha *= 0.5) {
    m_trial = m_v + alpha * m_dv;
    ++counters.force_evals;
    const double phi = objective(m, h, m_trial);
    if (std::isfinite(phi) && phi <= m_phi - kArmijo * alpha * slope) {
      m_v = m_trial;
      m_phi = phi;
      return true;
    }
  }
  return false;
}

void ImplicitEulerNewton::start_step(const Model& m, const SolverOptions& o, double t_end, double h,
                                     const Matrix3X& x, const Matrix3X& v) {
  m_x0 = x;
  m_v0 = v;
  m_v = v;
  m_contacts.clear();
  m_barrier_contacts.clear();
  m_t_end = t_end;
  m_lift_work = 0.0;
  m_solver.start_step();
  if (o.contacts == ContactMode::in_solve)
    find_contact_constraints(m, t_end, h, x, v, m_released, m_contacts);
  m_use_barrier = o.contacts == ContactMode::barrier && !m_barrier.empty();
  if (m_use_barrier) start_barrier(m, t_end, h);
  // the first guess x0 + h v0, with each contact's normal velocity fixed
  for (const ContactConstraint& c : m_contacts)
    m_v.col(c.particle) += (c.normal_velocity - c.normal.dot(m_v.col(c.particle))) * c.normal;
  // the dampers' directions are frozen at the step's start
  linearize_springs(m.springs, m_x0, o.clamp_compressed, m_lin0);
  if (m_use_barrier) choose_barrier_guess(m, h);
}

void ImplicitEulerNewton::choose_barrier_guess(const Model& m, double h) {
  // x0 + h v0 (good in free flight) or x0 itself (at rest relative to the colliders), whichever
  // has the lower objective: a particle that x0 + h v0 would put inside a collider is stopped
  // there, and its neighbours' stretch can make that guess far worse than standing still
  const double inertial = objective(m, h, m_v);
  m_dv.setZero();
  m_barrier.make_feasible(m, m_t_end, h, m_x0, m_dv);
  if (objective(m, h, m_dv) < inertial) m_v = m_dv;
}

void ImplicitEulerNewton::newton_direction(const Model& m, const SolverOptions& o, double h,
                                           double eta, Counters& counters) {
  // newton system A dv = -grad Phi at the iterate, filtered at held axes and contacts
  m_x = m_x0 + h * m_v;
  // after the first clamped_iterations, the direction comes from the exact matrix, preconditioned
  // by the clamped one, and CG stops where the exact matrix curves down (truncated Newton)
  const int iteration = static_cast<int>(m_history.size()) - 1;
  const bool exact = !m_direct && o.clamp_compressed && iteration >= o.clamped_iterations;
  linearize_springs(m.springs, m_x, o.clamp_compressed, m_lin, exact ? &m_lin_exact : nullptr);
  // the conjugate gradients apply A matrix-free and need only its diagonal blocks
  if (m_direct)
    m_matrix.assemble(m, m_lin, m_lin0, h);
  else
    m_matrix.assemble_diagonal_blocks(m, m_lin, m_lin0, h);
  m_matrix.apply_contacts(m, m_contacts, m_direct);
  if (m_use_barrier) add_barrier_blocks(h);
  CgResult cg;
  if (exact) {
    cg = m_solver.solve(m, m_matrix, m_lin_exact, m_lin, m_lin0, h, m_rhs, m_dv, eta,
                        o.cg_max_iterations, m_contacts, true);
  }
  // no step before the first direction of negative curvature: the clamped matrix's direction
  if (!exact || (cg.negative_curvature && cg.iterations == 0)) {
    counters.cg_iterations += cg.negative_curvature ? 1 : 0;  // the product that found it
    cg = m_solver.solve(m, m_matrix, m_lin, m_lin, m_lin0, h, m_rhs, m_dv, eta, o.cg_max_iterations,
                        m_contacts);
  }
  // a stop at negative curvature still made that direction's product
  counters.cg_iterations += cg.iterations + (cg.negative_curvature ? 1 : 0);
  if (cg.relative_residual > eta && !cg.negative_curvature) ++counters.cg_unconverged;
  m_dv = (m.free.array() > 0.0).select(m_dv, 0.0);
  remove_normal_parts(m_contacts, m_dv);
}

bool ImplicitEulerNewton::trust_region_iteration(const Model& m, const SolverOptions& o, double h,
                                                 double eta, Counters& counters) {
  // the model's matrix is the exact one; the preconditioner (its diagonal blocks and coarse
  // grid) comes from the clamped one, which is positive definite
  m_x = m_x0 + h * m_v;
  linearize_springs(m.springs, m_x, true, m_lin, &m_lin_exact);
  m_matrix.assemble_diagonal_blocks(m, m_lin, m_lin0, h);
  m_matrix.apply_contacts(m, m_contacts, false);
  if (m_use_barrier) add_barrier_blocks(h);
  const TrustRegionCgResult cg =
      m_solver.solve_trust_region(m, m_matrix, m_lin_exact, m_lin, m_lin0, h, m_rhs, m_weights,
                                  m_radius, m_dv, eta, o.cg_max_iterations, m_contacts);
  counters.cg_iterations += cg.iterations;
  if (!cg.on_boundary && cg.relative_residual > eta) ++counters.cg_unconverged;
  m_dv = (m.free.array() > 0.0).select(m_dv, 0.0);
  remove_normal_parts(m_contacts, m_dv);
  // the ratio of Phi's actual decrease to the model's
  const double step = std::sqrt((m_dv.array().square() * m_weights.array()).sum());
  m_trial = m_v + m_dv;
  ++counters.force_evals;
  const double phi = objective(m, h, m_trial);
  const double actual = m_phi - phi;
  const double predicted = cg.predicted_decrease;
  const bool roundoff = predicted <= kRoundoff * std::abs(m_phi);
  const double ratio = predicted > 0.0 ? actual / predicted : -1.0;
  const bool accept = std::isfinite(phi) && actual > 0.0 && (roundoff || ratio >= kAcceptRatio);
  // the region follows the model's quality
  if (!accept || (!roundoff && ratio < kShrinkRatio))
    m_radius = kShrink * std::min(step, m_radius);
  else if (ratio > kGrowRatio && cg.on_boundary)
    m_radius *= 2.0;
  if (!accept) return false;
  m_v = m_trial;
  m_phi = phi;
  return true;
}

void ImplicitEulerNewton::step(const Model& m, const SolverOptions& o, double t_end, double h,
                               Matrix3X& x, Matrix3X& v, Counters& counters) {
  start_step(m, o, t_end, h, x, v);
  // the barrier's two guesses were two evaluations more
  counters.force_evals += m_use_barrier ? 4 : 2;
  m_residual = residual(m, h, m_v);
  m_phi = objective(m, h, m_v);
  m_history.clear();
  m_history.push_back(m_phi);
  m_residuals.clear();
  m_residuals.push_back(m_residual);
  const bool adaptive = o.cg_forcing == CgForcing::adaptive;
  double eta = adaptive ? std::max(o.cg_tolerance, kForcingMax) : o.cg_tolerance;
  double residual_before = m_residual;
  // the tolerance is on the residual's acceleration, |M^-1 residual| / h, so that what a
  // converged step leaves shrinks with the step (a velocity tolerance would leave its own
  // error T tolerance over a run, whatever h)
  const double velocity_tolerance = o.newton_tolerance * h;
  const bool trust_region = o.newton == NewtonMethod::trust_region;
  if (trust_region && !(m_radius > 0.0)) {
    // the first step's region: free fall's velocity change over the step in the mass norm
    const double g = std::max(m.gravity.norm(), 1.0);
    m_radius = h * g * std::sqrt(m_weights.sum() / 3.0);
  }
  for (int it = 0; it < o.newton_iterations && m_residual > velocity_tolerance; ++it) {
    ++counters.newton_iterations;
    if (adaptive && it > 0) {
      eta = next_forcing(eta, m_residual / residual_before, o.cg_tolerance);
      eta = forcing_for_tolerance(eta, m_residual, velocity_tolerance);
    }
    residual_before = m_residual;
    if (trust_region) {
      // a rejected step leaves m_v, its residual and its Phi; the region shrinks
      if (trust_region_iteration(m, o, h, eta, counters)) {
        ++counters.force_evals;
        m_residual = residual(m, h, m_v);
      }
      m_history.push_back(m_phi);
      m_residuals.push_back(m_residual);
      if (!(m_radius > 0.0)) break;
      continue;
    }
    newton_direction(m, o, h, eta, counters);
    double slope = m_dv.cwiseProduct(m_rhs).sum();
    // a step that does not descend (no clamp, or a failed solve): S M^-1 times -grad Phi
    if (!(slope > 0.0)) {
      for (int r = 0; r < 3; ++r) m_dv.row(r) = m_rhs.row(r).cwiseProduct(m.inv_mass.transpose());
      remove_normal_parts(m_contacts, m_dv);
      slope = m_dv.cwiseProduct(m_rhs).sum();
    }
    // a failed line search leaves m_v, so m_rhs and m_impulse still belong to it
    if (!line_search(m, h, slope, counters)) break;
    ++counters.force_evals;
    m_residual = residual(m, h, m_v);
    m_history.push_back(m_phi);
    m_residuals.push_back(m_residual);
  }
  if (m_residual > velocity_tolerance) ++counters.newton_unconverged;
  finish_contacts(x.cols());
  if (m_use_barrier) finish_barrier(h);
  // held axes have v = 0 exactly, so x stays x0 there
  x = m_x0 + h * m_v;
  v = m_v;
}

void ImplicitEulerNewton::finish_contacts(Eigen::Index particles) {
  m_contact_work = 0.0;
  m_collider_work = 0.0;
  m_contact_impulse.setZero();
  m_released.assign(static_cast<size_t>(particles), 0);
  for (size_t k = 0; k < m_contacts.size(); ++k) {
    const ContactConstraint& c = m_contacts[k];
    // the constraint force J / h over the step's displacement h v: J (n . v), of which the
    // collider's motion does J (n . v_c) and the rest is relative to it
    const double collider = m_impulse[k] * c.normal.dot(c.collider_velocity);
    m_collider_work += collider;
    m_contact_work += m_impulse[k] * c.normal_velocity - collider;
    m_contact_impulse += m_impulse[k] * c.normal;
    // a contact that pulled its particle in lets go next step
    if (m_impulse[k] < 0.0) m_released[c.particle] = 1;
  }
}

void ImplicitEulerNewton::start_barrier(const Model& m, double t_end, double h) {
  // a particle on or inside a collider at the step's start is lifted out first; the lift's
  // work is its change of the potential energies (velocities are untouched)
  m_trial = m_x0;
  if (m_barrier.lift_out(m, t_end - h, m_x0) > 0) {
    double work = elastic_energy(m.springs, m_x0) - elastic_energy(m.springs, m_trial);
    for (Eigen::Index p = 0; p < m_x0.cols(); ++p)
      work -= m.mass[p] * m.gravity.dot(m_x0.col(p) - m_trial.col(p));
    m_lift_work = work;
  }
  m_barrier.make_feasible(m, t_end, h, m_x0, m_v);
  // friction lagged from the step's start
  m_barrier.friction_contacts(m, t_end, h, m_x0, m_friction_found);
  m_friction.start(m_friction_found, h);
}

void ImplicitEulerNewton::add_barrier_blocks(double h) {
  m_block_particles.clear();
  m_block_values.clear();
  for (const BarrierContact& b : m_barrier_contacts) {
    m_block_particles.push_back(b.particle);
    m_block_values.push_back((h * h * b.stiffness) * b.normal * b.normal.transpose());
  }
  m_friction.add_blocks(m_v, h * h, m_block_particles, m_block_values);
  m_matrix.add_particle_blocks(m_block_particles, m_block_values, m_direct);
}

void ImplicitEulerNewton::finish_barrier(double h) {
  // the force at the step's end over the step's displacement h v, as backward Euler applies it;
  // the colliders' motion does its impulse times their velocity, the rest is relative to them
  m_contact_work = m_lift_work;
  for (const BarrierContact& b : m_barrier_contacts) {
    const Vector3 impulse = (h * b.force) * b.normal;
    const double collider = impulse.dot(b.collider_velocity);
    m_collider_work += collider;
    m_contact_work += impulse.dot(m_v.col(b.particle)) - collider;
    m_contact_impulse += impulse;
  }
  if (m_friction.empty()) return;
  m_trial.setZero();
  m_friction.add_forces(m_v, m_trial);
  const double collider = h * m_friction.collider_power(m_v);
  m_collider_work += collider;
  m_contact_work += h * m_trial.cwiseProduct(m_v).sum() - collider;
  m_contact_impulse += h * m_trial.rowwise().sum();
}

}  // namespace cloth
