#include "harness/stability/growth_states.hpp"

#include <algorithm>
#include <cmath>

#include "cloth/analysis/linear_stability.hpp"
#include "cloth/model/model.hpp"
#include "harness/engines/engine_factory.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/run/runner.hpp"
#include "harness/sweeps/sweep.hpp"

namespace clothbench {

namespace {

double kinetic_energy(const cloth::Matrix3X& v, const cloth::VectorX& mass) {
  double e = 0;
  for (Eigen::Index p = 0; p < v.cols(); ++p) e += 0.5 * mass[p] * v.col(p).squaredNorm();
  return e;
}

cloth::MapState state_of(const cloth::Simulator& sim) {
  return {sim.positions(), sim.velocities(), sim.time()};
}

/// The reference engine: the custom engine of the scenario (the first one, or a default one
/// when it has none) with rk4.
EngineSpec reference_engine(const Scenario& sc, double dt) {
  EngineSpec e;
  for (const EngineSpec& s : sc.engines)
    if (s.kind == EngineKind::custom) {
      e = s;
      break;
    }
  e.kind = EngineKind::custom;
  return with_integrator_and_dt(e, cloth::Integrator::rk4, dt);
}

}  // namespace

double growth_reference_dt(const Scenario& sc, double rk4_limit) {
  double dt = sc.engines.empty() ? 1e-3 : sc.engines.front().dt;
  for (const EngineSpec& e : sc.engines) dt = std::min(dt, e.dt);
  // an implicit engine's large step says nothing of what rk4 can take
  dt = std::min(dt / 4, kReferenceLimitFraction * rk4_limit);
  return std::max(dt, kGrowthWindow / double(kGrowthReferenceSteps));
}

std::vector<GrowthState> growth_states(const Scenario& sc) {
  return growth_states(
      sc, cloth::predicted_stable_dt(cloth::Integrator::rk4,
                                     cloth::linear_spectrum(cloth::build_model(sc.scene))));
}

std::vector<GrowthState> growth_states(const Scenario& sc, double rk4_limit, std::string* warning) {
  const double dt = growth_reference_dt(sc, rk4_limit);
  const cloth::Model model = cloth::build_model(sc.scene);
  auto sim = make_engine(reference_engine(sc, dt), sc.scene);

  // walk the window, keeping the fastest state and the one with the most contacts
  GrowthState start{"start", state_of(*sim), 0};
  GrowthState fastest{"fastest", start.state, 0}, contact{"contact", start.state, 0};
  double fastest_energy = kinetic_energy(start.state.v, model.mass);
  const long long steps = std::llround(kGrowthWindow / dt);
  for (long long n = 0; n < steps; ++n) {
    // Ctrl-C stops the walk at once: on a fine grid it is thousands of rk4 steps
    if (interrupt_requested()) throw Interrupted();
    sim->step(dt);
    if (!sim->positions().allFinite() || !sim->velocities().allFinite()) {
      // what came before was the blow-up growing: the start only
      if (warning)
        *warning = "the reference (rk4 at " + format_double(dt) +
                   " s) stopped being finite at t = " + format_double(sim->time()) +
                   " s; its growth states are the start only";
      return {start};
    }
    const double e = kinetic_energy(sim->velocities(), model.mass);
    if (e > fastest_energy) {
      fastest_energy = e;
      fastest = {"fastest", state_of(*sim), sim->contacts()};
    }
    if (sim->contacts() > contact.contacts) contact = {"contact", state_of(*sim), sim->contacts()};
  }

  std::vector<GrowthState> states{start};
  if (fastest.state.t > 0) states.push_back(fastest);
  if (contact.contacts > 0) states.push_back(contact);
  return states;
}

}  // namespace clothbench
