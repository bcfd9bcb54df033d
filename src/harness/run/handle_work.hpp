#pragma once
/// @file handle_work.hpp
/// The work the scene's handles do on the cloth, booked by the harness alike for every engine
/// (frames.csv's handle_work). A handle's holder moves its particles along the prescribed path,
/// so it supplies whatever force keeps them there: R = m a - F - m g, with F the scene's spring,
/// damper (and hinge bending) forces and the air's drag on them. Its work over a step is
///   W = [KE_h(t1) - KE_h(t0)] - 1/2 (G(t0+) + G(t1)) . (d(t1) - d(t0)),   G = F + m g,
/// summed over the handled particles (the trapezoidal rule on the load, the path's
/// displacement d), computed from the engine's own positions and velocities with the scene's
/// model. G(t0+) is the load just after the holder set the step's velocity (d(t1) - d(t0)) /
/// (t1 - t0) on its particles, which differs from the last step's where the path turns. A
/// scene without handles builds nothing and pays nothing.

#include <vector>

#include "cloth/model/model.hpp"
#include "cloth/model/types.hpp"

namespace clothbench {

/// Books the handles' work step by step from the states an engine passes through.
class HandleWorkMeter {
 public:
  /// Starts at the engine's state (t, x, v); x, v 3 by #P (m, m/s). The model must outlive the
  /// meter.
  HandleWorkMeter(const cloth::Model& model, double t, const cloth::Matrix3X& x,
                  const cloth::Matrix3X& v);
  /// True when the scene has a handle (otherwise observe does nothing).
  bool active() const { return !m_particles.empty(); }
  /// Books the step from the last state observed to (t, x, v) and returns its work (J).
  double observe(double t, const cloth::Matrix3X& x, const cloth::Matrix3X& v);
  /// True when a handle's path moved over the last step observed.
  bool moved() const { return m_moved; }
  /// Work booked since the start (J).
  double work() const { return m_work; }

 private:
  /// G of every handled particle (3 by #H, N) and their kinetic energy (J) at (x, v).
  double load(const cloth::Matrix3X& x, const cloth::Matrix3X& v, cloth::Matrix3X& g);
  /// G at the last state observed with the handled particles at the velocities of the step to
  /// t (3 by #H, N, into m_load).
  void start_load(double t);

  const cloth::Model& m_model;
  cloth::SpringSet m_springs;      // the springs with a handled end (and the bending form)
  std::vector<int> m_particles;    // #H handled particles
  std::vector<int> m_handle_of;    // #H the handle each belongs to
  cloth::Matrix3X m_x, m_v;        // 3 by #P, the last state observed (m, m/s)
  cloth::Matrix3X m_load;          // 3 by #H, G (N)
  cloth::Matrix3X m_next;          // 3 by #H scratch
  cloth::Matrix3X m_force, m_buf;  // 3 by #P scratch
  double m_kinetic = 0;            // J, of the handled particles at the last state
  double m_t = 0;                  // s, of the last state
  double m_work = 0;               // J
  bool m_moved = false;
};

}  // namespace clothbench
