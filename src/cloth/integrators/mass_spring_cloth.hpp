#pragma once
/// @file mass_spring_cloth.hpp
/// The custom mass-spring cloth engine: the report's model with eight integrators.

#include <memory>
#include "cloth/solvers/conjugate_gradient.hpp"

#include "cloth/contact/self_contact.hpp"
#include "cloth/forces/spring_jacobians.hpp"
#include "cloth/integrators/implicit_euler.hpp"
#include "cloth/integrators/projective.hpp"
#include "cloth/model/integrator.hpp"
#include "cloth/model/model.hpp"
#include "cloth/model/scene.hpp"
#include "cloth/model/simulator.hpp"
#include "cloth/model/types.hpp"
#include "cloth/solvers/solver_options.hpp"

namespace cloth {

/// Within this of a collider's contact shell a particle counts as touched by the last contact
/// pass when set_state re-derives which particles rest (m): the pass leaves the particles it
/// touches on the shell to round-off (about 1e-16 m on metre coordinates).
constexpr double kRestingSlack = 1e-9;

/// The custom engine. The state starts at rest in the scene's flat grid.
class MassSpringCloth final : public Simulator {
 public:
  MassSpringCloth(const Scene& scene, const SolverOptions& options);
  /// The engine on a model built elsewhere (a mesh's, or a grid's springs as a general list).
  MassSpringCloth(Model model, const SolverOptions& options);

  void step(double dt) override;
  const Matrix3X& positions() const override { return m_x; }
  const Matrix3X& velocities() const override { return m_v; }
  double time() const override { return m_t; }
  double dissipated() const override { return m_dissipated; }
  /// Work of the contact projection and velocity response relative to the colliders, booked
  /// exactly every step: the pass's whole energy change less collider_work.
  double contact_work() const override { return m_contact_work; }
  /// Work of the moving colliders: each contact's impulse dotted with its collider's velocity.
  double collider_work() const override { return m_collider_work; }
  bool handles_act_by_force() const override { return true; }
  Counters counters() const override { return m_counters; }
  int contacts() const override { return m_contacts; }
  Vector3 contact_impulse() const override { return m_contact_impulse; }

  /// Replaces the state (tests start from chosen velocities). Held axes keep their values.
  /// @param x  3 by #P positions (m)
  /// @param v  3 by #P velocities (m/s)
  void set_state(const Matrix3X& x, const Matrix3X& v);
  bool can_set_state() const override { return true; }
  /// Puts the engine at time t (s) with positions x (3 by #P, m) and velocities v (3 by #P,
  /// m/s), held axes included; a held axis of a particle off the handles gets zero velocity, as
  /// every step leaves it (a handle's velocity enters only the holder's books). What the engine
  /// keeps between steps is re-derived from (x, t) or cleared: the particles resting on a
  /// collider (self-contact holds them) are those within kRestingSlack of a collider's shell,
  /// where the contact pass leaves what it touched; the self-contact candidate list is dropped
  /// (rebuilt at the next pass); line-search implicit Euler's contacts that let go (those that
  /// pulled their particle in at the last step) are forgotten. So a run resumed from its own
  /// state repeats itself, except where the last contact pass moved a particle it touched off
  /// the shell (friction on a curved shape, the self-contact pass) or a solve's contact was
  /// letting go. xpbd's multipliers, the implicit solvers' iterates and projective's factors
  /// (a function of dt) carry nothing between steps.
  void set_state(const Matrix3X& x, const Matrix3X& v, double t) override;
  const Model& model() const { return m_model; }
  const SolverOptions& options() const { return m_options; }
  /// The line-search Newton solver of implicit Euler; null in the other modes.
  const ImplicitEulerNewton* newton() const { return m_newton.get(); }
  /// The self-contact pass; null when the cloth has no self-collision.
  const SelfContact* self_contact() const { return m_self.get(); }
  /// What the last step's self-contact pass did (all zero without self-collision).
  const SelfContactStats& self_contact_stats() const { return m_self_stats; }

  /// Accelerations at state (x, v), held axes zeroed; counts one force evaluation.
  /// @param a  3 by #P accelerations (m/s^2), written
  /// @return power dissipated by dampers and drag at that state (W)
  double accelerations(const Matrix3X& x, const Matrix3X& v, Matrix3X& a);

 private:
  /// One step of the integrator alone.
  void integrate(double h);
  /// One classic Runge-Kutta step; returns the energy the dampers and drag took out (J).
  double step_rk4(double h);
  void step_implicit_euler(double h);
  void step_imex_euler(double h);
  /// Particles the line-search solve held on a collider with a pushing impulse that the
  /// contact pass after it did not count (m_touched).
  int held_in_solve_only() const;
  /// Resolves collider contacts and then self-contact after a step and books their work in
  /// m_contact_work and m_collider_work.
  void resolve_contacts(double h);
  /// The self-contact pass over the step from m_x_start, with held, handled and resting
  /// particles (touched by the collider pass at this step's end and the last) infinitely heavy.
  void resolve_self_contact(double h);
  /// Gives the handle particles their path's velocity over the next step of h seconds.
  void start_handles(double h);
  /// Puts the handle particles exactly on their path at the step's end.
  void finish_handles();

  Model m_model;
  SolverOptions m_options;
  Matrix3X m_x, m_v;
  double m_t = 0;
  double m_dissipated = 0;     // J, dampers and drag
  double m_contact_work = 0;   // J, net work of the contact response relative to the colliders
  double m_collider_work = 0;  // J, work of the moving colliders' motion
  int m_contacts = 0;          // particle-collider contacts of the last contact pass
  Vector3 m_contact_impulse = Vector3::Zero();  // N s, the colliders' impulse so far
  Counters m_counters;

  // scratch, sized once
  Matrix3X m_force, m_buf;
  Matrix3X m_x1, m_v1;                  // stage states
  Matrix3X m_x_start;                   // positions at the step's start (scenes with shapes)
  Matrix3X m_pass_free;                 // 3 by #P: the axes the contact pass after a step moves
  Matrix3X m_k1, m_k2, m_k3, m_k4;      // stage accelerations
  Matrix3X m_rhs, m_dv, m_diag, m_tmp;  // implicit solve
  SpringLinearization m_lin;
  CgWorkspace m_cg;
  std::unique_ptr<ImplicitEulerNewton> m_newton;   // implicit-euler with newton = line-search
  std::unique_ptr<ProjectiveSolver> m_projective;  // projective
  std::vector<char> m_touched;          // line-search or self-contact: particles the last contact
                                        // pass counted
  std::unique_ptr<SelfContact> m_self;  // self-collision; null without
  SelfContactStats m_self_stats;        // the last step's self-contact pass
  VectorX m_self_inv_mass;              // #P inverse masses in the self-contact pass
  std::vector<char> m_resting;          // #P: on a collider at the last step's end
  VectorX m_lambda;                     // xpbd: the springs' multipliers
};

}  // namespace cloth
