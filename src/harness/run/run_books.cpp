#include "harness/run/run_books.hpp"

#include "cloth/forces/energies.hpp"

namespace clothbench {

RunBooks::RunBooks(const cloth::Model& model, const cloth::Simulator& sim)
    : m_model(model),
      m_sim(sim),
      m_handles(model, sim.time(), sim.positions(), sim.velocities()),
      m_apart(m_handles.active() && !sim.handles_act_by_force()) {
  if (m_apart) m_last = balance(engine_books());
}

void RunBooks::observe() {
  if (!m_handles.active()) return;
  const double w = m_handles.observe(m_sim.time(), m_sim.positions(), m_sim.velocities());
  if (!m_apart) return;
  const double now = balance(engine_books());
  if (m_handles.moved()) m_residual += now - m_last - w;
  m_last = now;
}

double RunBooks::balance(const EnergyBooks& b) const {
  const double total =
      cloth::compute_energies(m_model, m_sim.positions(), m_sim.velocities()).total();
  return energy_error(total, b, 0.0);
}

}  // namespace clothbench
