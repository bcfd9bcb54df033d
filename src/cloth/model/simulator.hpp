#pragma once
/// @file simulator.hpp
/// The interface every engine implements: the custom cloth and each Bullet adapter alike.

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "cloth/model/types.hpp"

namespace cloth {

/// Machine-independent cost of a run.
struct Counters {
  std::int64_t steps = 0;
  std::int64_t force_evals = 0;    // full force evaluations
  std::int64_t cg_iterations = 0;  // conjugate-gradient iterations (implicit solvers)
  std::int64_t newton_iterations = 0;
  std::int64_t contact_tests = 0;           // particle-sphere distance tests
  std::int64_t cg_unconverged = 0;          // linear solves that stopped at the iteration limit
  std::int64_t newton_unconverged = 0;      // implicit steps whose Newton iteration ended (at its
                                            // limit or a failed line search) above its tolerance
  std::int64_t constraint_projections = 0;  // xpbd: one spring constraint projected once
  std::int64_t linear_solves = 0;           // projective: prefactored global solves (3 axes each)
  std::int64_t self_contact_tests = 0;      // self-contact narrow-phase pair tests
};

/// Thrown by an engine that cannot go on for a reason of its own (an external engine's process
/// crashed, hung, or broke the protocol): the run fails with this message, other runs go on.
struct EngineFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One engine running one scene. Particle order, masses and units are the scene's.
class Simulator {
 public:
  virtual ~Simulator() = default;
  /// Advances the state by dt seconds.
  virtual void step(double dt) = 0;
  /// Advances the state by steps steps of dt seconds each, as steps calls of step(dt) (the
  /// default); an engine behind a process boundary does them in one request.
  virtual void advance(double dt, int steps) {
    for (int s = 0; s < steps; ++s) step(dt);
  }
  /// Whether the runner should step this engine in batches (advance) between its checks
  /// rather than one step at a time (true for an engine that pays per request).
  virtual bool prefers_batches() const { return false; }
  /// 3 by #P positions (m).
  virtual const Matrix3X& positions() const = 0;
  /// 3 by #P velocities (m/s).
  virtual const Matrix3X& velocities() const = 0;
  /// Simulated time (s).
  virtual double time() const = 0;
  /// Energy taken out by the spring dampers and air drag since the start (J).
  virtual double dissipated() const = 0;
  /// Net work of the contact response since the start (J): the energy it added (lifting
  /// particles out of an obstacle against gravity and springs) minus the energy it removed
  /// (the normal velocity it cancels, friction); 0 for an engine that cannot separate it. The
  /// handles' work is not in it: the harness books that for every engine alike. Nor is the
  /// moving colliders' share (collider_work) in an engine that books that apart.
  virtual double contact_work() const { return 0.0; }
  /// Work of the moving colliders' motion since the start (J): each contact's impulse (or force
  /// times the step) dotted with its collider's velocity, so that contact_work keeps the work
  /// relative to the colliders; exactly 0 for static colliders, and 0 for an engine that cannot
  /// split its contact work (all of it stays in contact_work).
  virtual double collider_work() const { return 0.0; }
  /// True when the handles move their particles by force: the holder supplies exactly what
  /// cancels every other force on them (the custom engine), so the scene's forces give the
  /// holder's work. False for an engine that projects them onto their path.
  virtual bool handles_act_by_force() const { return false; }
  /// Particle-collider contacts (particles within a collider's shell) at the last step; -1 for
  /// an engine that cannot say.
  virtual int contacts() const { return -1; }
  /// Impulse the colliders have given the cloth since the start (N s); NaN for an engine that
  /// cannot say.
  virtual Vector3 contact_impulse() const { return Vector3::Constant(NAN); }
  /// Energy change the engine's books cannot attribute (J): for a Bullet engine, the whole
  /// energy balance of the steps in which a contact acted (its contact work and its scheme's
  /// error in that step, which Bullet does not report apart); 0 for the custom engine.
  virtual double unbooked() const { return 0.0; }
  /// Cost so far.
  virtual Counters counters() const = 0;
  /// Whether set_state can put this engine into a given state (the growth measurement needs
  /// it).
  virtual bool can_set_state() const { return false; }
  /// Puts the engine at simulated time t (s) with positions x (3 by #P, m) and velocities v
  /// (3 by #P, m/s), as if a run had arrived there: the next step(dt) is then a function of
  /// (x, v, t, dt) alone, whatever the engine did before (caches between steps, such as warm
  /// starts, contact or resting flags, are re-derived from the state or cleared, and what
  /// cannot be is documented by the engine). Held axes and handles take x as given. The
  /// books (dissipated, contact_work, collider_work, unbooked, counters) are kept. Throws
  /// std::logic_error when !can_set_state().
  virtual void set_state(const Matrix3X& x, const Matrix3X& v, double t);
};

inline void Simulator::set_state(const Matrix3X&, const Matrix3X&, double) {
  throw std::logic_error("set_state: this engine cannot set its state");
}

}  // namespace cloth
