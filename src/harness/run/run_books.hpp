#pragma once
/// @file run_books.hpp
/// The energy books of one engine's run: what the engine books itself (dissipated,
/// contact_work, collider_work, unbooked) and what the harness books for every engine alike (the
/// handles' work, handle_work.hpp).

#include "cloth/model/model.hpp"
#include "cloth/model/simulator.hpp"
#include "harness/run/handle_work.hpp"
#include "harness/run/metrics.hpp"

namespace clothbench {

/// What an engine has booked of its energy so far, with the handles' work the harness books
/// (handle_work.hpp). An engine whose handles do not act by force (they are projected onto
/// their path) cannot be held to the scene's forces on a step in which a handle moved: that
/// step's balance beyond the handles' work goes to unbooked, so its energy error stays the
/// scheme's own on the other steps.
class RunBooks {
 public:
  /// Starts at sim's current state; model (the engine's scene's) and sim must outlive the
  /// books.
  RunBooks(const cloth::Model& model, const cloth::Simulator& sim);
  /// Books the step (or batch of steps) the engine has just taken.
  void observe();
  /// The books so far.
  EnergyBooks now() const {
    EnergyBooks b = engine_books();
    b.handle_work = m_handles.work();
    b.unbooked += m_residual;
    return b;
  }

 private:
  EnergyBooks engine_books() const {
    EnergyBooks b;
    b.dissipated = m_sim.dissipated();
    b.contact_work = m_sim.contact_work();
    b.collider_work = m_sim.collider_work();
    b.unbooked = m_sim.unbooked();
    return b;
  }
  /// The engine's balance with its own books alone (J): total + dissipated - contact_work -
  /// collider_work - unbooked.
  double balance(const EnergyBooks& b) const;

  const cloth::Model& m_model;
  const cloth::Simulator& m_sim;
  HandleWorkMeter m_handles;
  bool m_apart;           // the handles' steps' residual goes to unbooked
  double m_last = 0;      // J, the engine's balance after the last step observed
  double m_residual = 0;  // J, booked as unbooked by the harness
};

}  // namespace clothbench
