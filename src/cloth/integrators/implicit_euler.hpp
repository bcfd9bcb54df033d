#pragma once
/// @file implicit_euler.hpp
/// Backward Euler by Newton's method on the step's incremental potential, with a backtracking
/// line search (the "optimisation integrator" view). In velocities v (x = x0 + h v):
///
///   Phi(v) = 1/2 |v - v0 - h g|_M^2 + E(x0 + h v) + h/2 (c sum_s (d0_s . (v_q - v_p))^2 + drag
///   |v|^2)
///
/// E is the elastic energy, d0_s spring s's direction at the step's start. The last term is the
/// Rayleigh potential of the spring dampers with their directions frozen at x0, the directions
/// Baraff and Witkin's linearised step uses for D, so -grad Phi = h f(x, v) - M (v - v0) is the
/// backward-Euler residual with that damper, and the Hessian is A = M + h drag - h D0 - h^2 K.
/// The definiteness fix (clamp_compressed) changes only the matrix's K; Phi and its gradient are
/// the true ones, so the equilibrium does not move. With the fix the Newton model is wrong
/// wherever springs are compressed, and convergence there is only linear; so after the first
/// clamped_iterations of a step the CG solvers apply the exact matrix, precondition with the
/// clamped one, and stop at the first direction of negative curvature (truncated Newton: the
/// iterate reached is still a descent direction), falling back to the clamped matrix's
/// direction when that is the very first one.
///
/// With newton = trust-region the same Phi, residual test and contacts are minimised in a trust
/// region instead: each iteration solves min m(dv) = -r.dv + 1/2 dv.A dv over |dv|_M <= radius
/// by Steihaug-Toint CG (trust_region_cg.hpp) with A the exact matrix (compressed springs'
/// negative stiffness kept), preconditioned by the clamped one; a direction of negative
/// curvature is followed to the region's edge, where a line search's backtracking would stop
/// short. The step is taken only when Phi falls (by kAcceptRatio of the model's decrease at
/// least), so every iterate lowers Phi as the line search's do; the radius shrinks when the
/// ratio of Phi's fall to the model's is poor and grows when it is good on the edge. The region
/// is in the mass norm |dv|_M (sqrt of twice the velocity change's kinetic energy): fixed over
/// a run, unlike the preconditioner's norm, which changes with every iterate's clamped matrix,
/// so one radius carries from one iteration and step to the next.

#include <memory>
#include <vector>

#include "cloth/contact/contact_barrier.hpp"
#include "cloth/model/model.hpp"
#include "cloth/model/simulator.hpp"
#include "cloth/solvers/implicit_matrix.hpp"
#include "cloth/solvers/newton_linear_solver.hpp"
#include "cloth/solvers/solver_options.hpp"

namespace cloth {

/// The smallest cloth (particles) for which `automatic` means two-level-cg.
constexpr int kTwoLevelMinParticles = 48 * 48;

/// The linear solver that `automatic` means for a line-search step on a cloth of that many
/// particles: two-level-cg from kTwoLevelMinParticles up, block-jacobi-cg below (README), and
/// block-jacobi-cg on a cloth that is not a grid (two-level-cg needs one: coarse_grid.hpp).
/// @param grid  false when the cloth's springs have a general list (SpringSet::list)
LinearSolver resolved_linear_solver(LinearSolver s, int particles, bool grid = true);

/// Newton with a line search or a trust region for one scene; scratch sized once.
class ImplicitEulerNewton {
 public:
  ImplicitEulerNewton(const Model& m, const SolverOptions& o);

  /// Advances x and v (each 3 by #P) by one backward-Euler step of h seconds that ends at
  /// t_end (s), with contacts in the solve if o.contacts is in_solve or barrier.
  void step(const Model& m, const SolverOptions& o, double t_end, double h, Matrix3X& x,
            Matrix3X& v, Counters& counters);

  /// Work of the last step's contact constraints relative to their colliders (J, negative when
  /// they took energy out): their whole work less collider_work.
  double contact_work() const { return m_contact_work; }
  /// Work of the last step's moving colliders (J): each contact's impulse (the barrier's and
  /// friction's force at the step's end times h) dotted with its collider's mean velocity over
  /// the step; exactly 0 for static colliders.
  double collider_work() const { return m_collider_work; }
  /// Impulse of the last step's contact constraints on the cloth (N s).
  const Vector3& contact_impulse() const { return m_contact_impulse; }
  /// The last step's contact constraints.
  const std::vector<ContactConstraint>& contacts() const { return m_contacts; }
  /// Their impulses along their normals (N s), in the same order.
  const std::vector<double>& impulses() const { return m_impulse; }

  /// The last step's barrier contacts at its end (contacts = "barrier"), one per particle and
  /// collider within the collider's margin.
  const std::vector<BarrierContact>& barrier_contacts() const { return m_barrier_contacts; }
  /// The particles the barrier acts on (#P flags): the others keep the contact pass.
  const std::vector<char>& barrier_covered() const { return m_barrier.covered(); }
  /// Forgets what carries from step to step (Simulator::set_state): which contacts let go and
  /// the trust region's radius, so that the next step is the first step of a run from there.
  void forget_history() {
    m_released.clear();
    m_radius = 0;
  }

  /// Phi at the start and after each Newton iteration of the last step (J).
  const std::vector<double>& objective_history() const { return m_history; }
  /// Largest |M^-1 residual| at the start and after each Newton iteration of the last step (m/s).
  const std::vector<double>& residual_history() const { return m_residuals; }
  /// Largest |M^-1 residual| after the last step (m/s).
  double last_residual() const { return m_residual; }

 private:
  /// solver: o.linear_solver resolved (not automatic)
  ImplicitEulerNewton(const Model& m, const SolverOptions& o, LinearSolver solver);
  /// Sets the step's start, contacts, first guess and frozen damper directions.
  void start_step(const Model& m, const SolverOptions& o, double t_end, double h, const Matrix3X& x,
                  const Matrix3X& v);
  /// Solves for m_dv, the filtered Newton direction at m_v, to relative residual eta.
  void newton_direction(const Model& m, const SolverOptions& o, double h, double eta,
                        Counters& counters);
  /// Books the contacts' work and impulse and which contacts let go.
  void finish_contacts(Eigen::Index particles);
  /// Books the barrier contacts' work and impulse over the step (contacts = "barrier").
  void finish_barrier(double h);
  /// Lifts particles that start on or inside a collider out of it, booking the energy the lift
  /// gives; then makes the first guess feasible (contacts = "barrier").
  void start_barrier(const Model& m, double t_end, double h);
  /// The first guess of a barrier step: the inertial one or standing still, the lower Phi.
  void choose_barrier_guess(const Model& m, double h);
  /// A's barrier blocks h^2 kappa b'' n n^T at the iterate's contacts.
  void add_barrier_blocks(double h);
  double objective(const Model& m, double h, const Matrix3X& v);
  double residual(const Model& m, double h, const Matrix3X& v);
  bool line_search(const Model& m, double h, double slope, Counters& counters);
  /// One trust-region iteration at m_v (newton = trust-region): the model's step by
  /// Steihaug-Toint CG within m_radius, taken if Phi falls enough; updates m_radius.
  /// @return true when the step was taken (m_v and m_phi moved)
  bool trust_region_iteration(const Model& m, const SolverOptions& o, double h, double eta,
                              Counters& counters);

  ImplicitMatrix m_matrix;
  NewtonLinearSolver m_solver;
  SpringLinearization m_lin0, m_lin, m_lin_exact;
  Matrix3X m_weights;   // 3 by #P: the trust region's mass norm (kg), 0 on held axes
  double m_radius = 0;  // the trust region's radius, |dv|_M (kg^1/2 m/s), kept across steps
  Matrix3X m_x0, m_v0, m_v, m_x, m_trial, m_dv, m_force, m_damp, m_zero, m_buf, m_rhs;
  std::vector<double> m_history, m_residuals;
  ColliderBarrier m_barrier;
  std::vector<BarrierContact> m_barrier_contacts;  // at the iterate m_v (residual())
  std::vector<FrictionContact> m_friction_found;   // start_barrier's scratch
  StepFriction m_friction;                         // this step's lagged friction
  std::vector<int> m_block_particles;              // add_barrier_blocks' scratch
  std::vector<Matrix3> m_block_values;
  bool m_use_barrier = false;  // this step
  double m_t_end = 0;          // s, this step's end
  double m_lift_work = 0;      // J, start_barrier's lift of this step
  std::vector<ContactConstraint> m_contacts;
  std::vector<double> m_impulse;  // per contact, along its normal (N s)
  std::vector<char> m_released;   // per particle: its last contact pulled it in
  Vector3 m_contact_impulse = Vector3::Zero();
  double m_contact_work = 0;   // J, relative to the colliders
  double m_collider_work = 0;  // J, the colliders' motion
  double m_phi = 0, m_residual = 0;
  bool m_direct = false;  // ldlt: A assembled whole
};

}  // namespace cloth
