#pragma once
/// @file simulator.hpp
/// The interface every engine implements: the custom cloth and each Bullet adapter alike.

#include <cstdint>
#include <string>

#include "cloth/types.hpp"

namespace cloth {

/// Machine-independent cost of a run.
struct Counters {
  std::int64_t steps = 0;
  std::int64_t force_evals = 0;    // full force evaluations
  std::int64_t cg_iterations = 0;  // conjugate-gradient iterations (implicit solvers)
  std::int64_t newton_iterations = 0;
  std::int64_t contact_tests = 0;   // particle-sphere distance tests
  std::int64_t cg_unconverged = 0;  // linear solves that stopped at the iteration limit
};

/// One engine running one scene. Particle order, masses and units are the scene's.
class Simulator {
 public:
  virtual ~Simulator() = default;
  /// Advances the state by dt seconds.
  virtual void step(double dt) = 0;
  /// 3 by #P positions (m).
  virtual const Matrix3X& positions() const = 0;
  /// 3 by #P velocities (m/s).
  virtual const Matrix3X& velocities() const = 0;
  /// Simulated time (s).
  virtual double time() const = 0;
  /// Energy taken out by damping, drag and contact since the start (J).
  virtual double dissipated() const = 0;
  /// Cost so far.
  virtual Counters counters() const = 0;
};

}  // namespace cloth
