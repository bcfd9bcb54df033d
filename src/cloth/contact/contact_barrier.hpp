#pragma once
/// @file contact_barrier.hpp
/// Contact with the scene's rigid colliders as a barrier potential inside implicit Euler's
/// incremental potential (newton = "line-search", contacts = "barrier").
///
/// Each free particle p near collider c carries the energy kappa_pc b(d), d the particle's
/// signed distance to the collider's surface where the collider ends the step, with the
/// log barrier of Li et al. (2020, "Incremental Potential Contact", eq. 6):
///
///   b(d) = -(d - dhat)^2 ln(d / dhat)  for 0 < d < dhat,  0 from dhat on,  +inf at d <= 0.
///
/// b is twice continuously differentiable at dhat and convex on (0, dhat), so the force
/// -kappa b'(d) n grows from zero at the layer's top (dhat, the collider's margin) without
/// bound as the particle nears the surface: a particle never reaches it, whatever the step.
/// The stiffness kappa_pc = m_p kBarrierAcceleration / dhat_c is a law fixed by the scene (not
/// by the step), so a run converges as dt shrinks. Because the contact force is the gradient
/// of a potential that is part of what the step minimises, a static collider can take energy
/// out (implicit Euler's dissipation) but never put it in: over the run its work is at most
/// -B(x), and the cloth's mechanical energy plus B never rises (tests/cloth/test_barrier.cpp).
/// The barrier is inelastic: a collider with restitution is refused in this mode by the
/// scenario loader.
///
/// Friction is IPC's lagged dissipative potential (Li et al. 2020, section 5): for a particle
/// within a collider's layer at the step's start, with normal force lambda (the barrier's, at
/// the step's start) and u the particle's tangential displacement relative to the collider over
/// the step, D(u) = mu lambda f0(|u|), where f0 smooths |u| below eps = kFrictionSpeed h (f0' =
/// f1, f1(y) = 2 y / eps - y^2 / eps^2 below eps and 1 above). Its force -mu lambda f1(|u|)
/// u / |u| opposes the sliding and never exceeds mu lambda (Coulomb); a particle that slides
/// slower than kFrictionSpeed is held as by a stiff spring (static friction, approximately).
/// Its work on the cloth is never positive relative to the collider.

#include <vector>

#include "cloth/model/model.hpp"
#include "cloth/model/types.hpp"

namespace cloth {

/// The barrier's stiffness per unit of the particle's mass, over dhat (m/s^2): a particle
/// resting under gravity (9.8 m/s^2) sits at 0.82 dhat, and the force reaches 10 times its
/// weight at 0.08 dhat.
constexpr double kBarrierAcceleration = 100.0;

/// Below this sliding speed friction acts as a stiff spring, above it as Coulomb's (m/s).
constexpr double kFrictionSpeed = 1e-3;

/// b(d) for the layer dhat (m^2); +inf at d <= 0.
double barrier(double d, double dhat);
/// db/dd (m), <= 0 inside the layer.
double barrier_slope(double d, double dhat);
/// d^2b/dd^2 (1), >= 0 inside the layer.
double barrier_curvature(double d, double dhat);

/// One particle within a collider's layer.
struct BarrierContact {
  int particle = 0;
  Vector3 normal = Vector3::UnitY();  // outward unit normal of the collider at the particle
  double distance = 0;                // m, to the surface
  double force = 0;                   // N, along the normal, >= 0: -kappa b'(d)
  double stiffness = 0;               // N/m, kappa b''(d): the normal block of the Hessian
  Vector3 collider_velocity = Vector3::Zero();  // m/s, the collider's mean over the step (when
                                                // contacts() is given the step)
};

/// f0(y) for the smoothing length eps (m): y from eps on, a cubic below it.
double friction_f0(double y, double eps);
/// f1 = f0' (1).
double friction_f1(double y, double eps);

/// One particle's friction over a step, lagged from the step's start.
struct FrictionContact {
  int particle = 0;
  Vector3 normal = Vector3::UnitY();            // the collider's outward normal at the start
  Vector3 collider_velocity = Vector3::Zero();  // m/s, the collider's over the step
  double bound = 0;                             // N, mu lambda: the largest friction force
};

/// The barrier of every collider of a model over the particles free on every axis (a particle
/// with a held axis, handles' included, keeps the contact pass after the step).
class ColliderBarrier {
 public:
  explicit ColliderBarrier(const Model& m);

  /// True when the model has no collider.
  bool empty() const { return m_empty; }

  /// True for a particle the barrier acts on (#P flags).
  const std::vector<char>& covered() const { return m_covered; }

  /// B(x) with the colliders where they are at time t (J); +inf if a covered particle is on
  /// or inside a collider. x: 3 by #P positions (m).
  double energy(const Model& m, double t, const Matrix3X& x) const;

  /// The covered particles within a layer at x and t, one entry per particle and collider;
  /// with the step h (s) that ends at t, each with its collider's mean velocity over it.
  void contacts(const Model& m, double t, const Matrix3X& x, std::vector<BarrierContact>& out,
                double h = 0.0) const;

  /// Lifts each covered particle that is on or inside a collider at time t out along the
  /// normal to half the collider's margin (a state that began there, or was set there).
  /// @param x  3 by #P positions (m), changed
  /// @return the particles lifted
  int lift_out(const Model& m, double t, Matrix3X& x) const;

  /// Makes a step's first guess feasible: each covered particle whose x0 + h v is on or inside
  /// a collider at t_end moves with that collider over the step instead, which keeps the
  /// distance it started at (x0 must be outside every collider at t_end - h: lift_out).
  /// @param v  3 by #P velocities (m/s), changed
  void make_feasible(const Model& m, double t_end, double h, const Matrix3X& x0, Matrix3X& v) const;

  /// Adds each contact's force along its normal to f (3 by #P, N).
  static void add_forces(const std::vector<BarrierContact>& contacts, Matrix3X& f);

  /// The friction contacts of a step of h seconds that ends at t_end from positions x0: every
  /// covered particle within the layer of a collider with friction at t_end - h.
  void friction_contacts(const Model& m, double t_end, double h, const Matrix3X& x0,
                         std::vector<FrictionContact>& out) const;

 private:
  std::vector<char> m_covered;
  bool m_empty = true;
};

/// The friction of a step in velocities v (3 by #P, m/s; x = x0 + h v): its potential, its
/// force and its Hessian blocks (with respect to x), summed over contacts.
class StepFriction {
 public:
  /// Sets the step's contacts and length h (s).
  void start(std::vector<FrictionContact> contacts, double h);
  bool empty() const { return m_contacts.empty(); }
  const std::vector<FrictionContact>& contacts() const { return m_contacts; }

  /// Sum of mu lambda f0(|u|) (J).
  double energy(const Matrix3X& v) const;
  /// Adds -grad_x of it to f (3 by #P, N).
  void add_forces(const Matrix3X& v, Matrix3X& f) const;
  /// Sum over contacts of the friction force dotted with its collider's velocity (W).
  double collider_power(const Matrix3X& v) const;
  /// Appends each contact's 3 by 3 Hessian block times scale (positive semi-definite).
  void add_blocks(const Matrix3X& v, double scale, std::vector<int>& particles,
                  std::vector<Matrix3>& blocks) const;

 private:
  /// The contact's tangential displacement over the step (m).
  Vector3 sliding(const FrictionContact& c, const Matrix3X& v) const;
  /// The contact's friction force on its particle (N).
  Vector3 force(const FrictionContact& c, const Matrix3X& v) const;

  std::vector<FrictionContact> m_contacts;
  double m_h = 0;    // s
  double m_eps = 0;  // m, kFrictionSpeed h
};

}  // namespace cloth
