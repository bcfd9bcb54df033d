#pragma once
/// @file growth_states.hpp
/// The states a growth measurement starts from: a handful of states of one reference
/// trajectory, computed once at a small step and over a fixed window of time, so that they
/// are the same whatever the scenario's duration.
///
/// The reference is the custom engine with rk4 at a quarter of the smallest dt among the
/// scenario's engines, and at most kReferenceLimitFraction of rk4's predicted limit, over
/// kGrowthWindow seconds. A reference that still stops being finite gives the start state
/// only: the states just before a blow-up are the blow-up's, not the scene's.
/// The states: the start; the fastest-moving state (largest kinetic energy); and, when any
/// state of the window has the cloth on a collider, the one with the most collider contacts.

#include <string>
#include <vector>

#include "cloth/analysis/growth_rate.hpp"
#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// Length of the reference trajectory (s), whatever the scenario's duration.
constexpr double kGrowthWindow = 1.0;

/// Steps of the reference trajectory at most; a smaller dt is raised to keep to it.
constexpr long long kGrowthReferenceSteps = 200000;

/// The reference's step at most, as a fraction of rk4's predicted limit at the rest state: a
/// stretched, moving cloth is stiffer than at rest (tension adds transverse stiffness).
constexpr double kReferenceLimitFraction = 0.5;

/// One state the growth is measured at.
struct GrowthState {
  std::string label;      // "start", "fastest" or "contact"
  cloth::MapState state;  // positions, velocities and time
  int contacts = 0;       // particle-collider contacts of the reference engine there
};

/// The reference states of scenario sc (see the file comment), distinct states only (a
/// fastest state at t = 0 is the start).
/// @param rk4_limit  rk4's predicted stability limit of the scene (s; cloth::predicted_stable_dt)
/// @param warning    set to what went wrong when the reference blew up ("" otherwise)
std::vector<GrowthState> growth_states(const Scenario& sc, double rk4_limit,
                                       std::string* warning = nullptr);

/// The same, with rk4's limit predicted here.
std::vector<GrowthState> growth_states(const Scenario& sc);

/// The time step of the reference trajectory (s).
/// @param rk4_limit  rk4's predicted stability limit of the scene (s)
double growth_reference_dt(const Scenario& sc, double rk4_limit);

}  // namespace clothbench
