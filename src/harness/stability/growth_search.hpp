#pragma once
/// @file growth_search.hpp
/// The stability limit of one engine configuration measured by the growth of perturbations
/// (`clothbench stability --method growth`), without waiting for a blow-up.
///
/// At each time step dt tried and at each reference state (growth_states.hpp) the growth rate
/// of the one-step map, sigma(dt) = ln(rho) / dt with rho its largest amplification
/// (cloth::estimate_growth), is compared with the physical rate of the same state: the same
/// rate measured over the same time in eight steps of dt / 8 (a swinging or buckling cloth
/// grows too, at a rate that does not depend on dt). dt is unstable when at some state
///   sigma_low(dt) - max(physical rate, 0) > growth_tol,
/// sigma_low the one-step rate the estimate guarantees: sigma(dt) itself when the estimate
/// converged, else the rate at the low end of its error, |theta| - sqrt(residual)
/// (lower_rate): an estimate that ran out of products shows growth only that far.
/// A state at which nothing grows faster than growth_tol (sigma_low(dt) <= growth_tol) is stable
/// there without the physical rate being measured. A state whose map is not differentiable
/// (a contact switching under the perturbation) gives no number and no verdict; when every
/// state is so the search ends there. The limit is bracketed from a starting dt by a first
/// step (5 % from a prediction) either way, then doubling or halving, then bisected on a log
/// scale: the criterion is not smooth at the limit (a square-root branch for symplectic
/// Euler), so nothing faster than bisection is assumed.

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "cloth/analysis/growth_rate.hpp"
#include "cloth/model/integrator.hpp"
#include "cloth/model/model.hpp"
#include "harness/scenario/scenario.hpp"
#include "harness/stability/growth_states.hpp"

namespace clothbench {

/// Default growth tolerance (1/s): a perturbation may grow at most tenfold per second faster
/// than the physical growth of the state (docs/stability.md says why).
inline const double kDefaultGrowthTol = 2.302585092994046;  // ln 10

/// The bracket's first step from a predicted limit (factor): on the seed and flag scenes the
/// custom engines' growth limits are within 2.2 % of the prediction in 9 rows of 11
/// (docs/methods.md), and a bracket of 5 % leaves two bisections where one of 2 leaves six.
constexpr double kPredictionFirstStep = 1.05;

/// A growth verdict near the physics: the states that decide it grow at most this fraction of
/// their one-step rate faster than their physical rate. On the seed and flag scenes and the
/// fabric example (docs/methods.md) every row whose growth limit agrees with the blow-up search
/// has a deciding state 31 % or more above its physical rate, and every row where the two
/// disagree by more than a factor of 2 has none above 11 %.
constexpr double kNearPhysicalFraction = 0.2;

/// Options of one growth search.
struct GrowthSearchOptions {
  double perturbation = 1e-7;             // relative finite-difference size
  double growth_tol = kDefaultGrowthTol;  // 1/s
  double rel_tol = 0.02;                  // bisection until first_unstable / stable - 1 <= this
  double dt_max = 0.1;                    // s, no dt above this is tried
  double first_step = 2;                  // the bracket's first step from the start (factor)
  int max_halvings = 10;                  // halvings below the start before giving up
  double max_seconds = 0;                 // s of wall clock the search may take before it
                                          // stops as a timeout (0: no limit)
  bool decide_early = true;  // stop each estimate once its side of the verdict is decided
                             // (false: every estimate to its residual of 1e-7)
};

/// The growth at one state and dt.
struct StateGrowth {
  std::string label;  // the reference state's label
  int contacts = 0;   // the reference engine's collider contacts at that state
  bool smooth = true;
  std::string nonsmooth_reason;
  double rate = std::numeric_limits<double>::quiet_NaN();           // 1/s, sigma(dt)
  double lower_rate = std::numeric_limits<double>::quiet_NaN();     // 1/s, sigma_low(dt)
  double physical_rate = std::numeric_limits<double>::quiet_NaN();  // 1/s, at dt / 8 (NaN: not
                                                                    // needed)
  bool unstable = false;
  bool physical_decided = false;   // physical_rate stopped once its side was decided
  cloth::GrowthEstimate estimate;  // of the one-step map
};

/// What a growth search found.
struct GrowthLimit {
  double stable_dt = std::numeric_limits<double>::quiet_NaN();  // s, largest dt judged stable
  double first_unstable_dt = std::numeric_limits<double>::infinity();  // s, smallest unstable
  double growth_rate = std::numeric_limits<double>::quiet_NaN();       // 1/s, sigma at
                                                                       // first_unstable_dt
  double physical_rate = std::numeric_limits<double>::quiet_NaN();     // 1/s, of that state
  std::string cause;     // where the growth is: contact or free states, non-smooth states
  cloth::Matrix3X mode;  // 3 by #P growing mode at first_unstable_dt (empty: none)
  std::array<double, 3> mode_energy{std::numeric_limits<double>::quiet_NaN(),
                                    std::numeric_limits<double>::quiet_NaN(),
                                    std::numeric_limits<double>::quiet_NaN()};
  // the mode's linearised spring energy by kind (structural, shear, bend), as fractions
  long long steps = 0;  // engine steps the search took (all maps, all states)
  int judged = 0;       // time steps judged
};

/// The largest relative excess of the states judged unstable, (rate - max(physical, 0)) / rate,
/// in *fraction, and that state's index (-1 and NaN when none is smooth and unstable). The
/// verdict is near the physics when it is at most kNearPhysicalFraction: the step then
/// reproduces each state's physical growth to that fraction, and the excess is as well explained
/// by the estimates' error or the scheme's accuracy on a growing mode as by a step-size
/// instability.
int largest_excess(const std::vector<StateGrowth>& states, double* fraction);

/// The one-step rate an estimate of `steps` steps of dt guarantees (1/s): its rate when it
/// converged or overflowed, else ln(|theta| - sqrt(residual)) / (steps dt), the low end of the
/// Ritz value's error (cloth::decided_side says why the square root); -infinity when that end
/// is not positive. On a flat fabric sheet the free bending modes' Jordan blocks leave Arnoldi
/// unconverged after its 120 products with Ritz values above 1 by less than their error
/// (docs/methods.md).
double lower_rate(const cloth::GrowthEstimate& e, double dt, int steps = 1);

/// Judges dt for one engine configuration at every state.
std::vector<StateGrowth> judge_growth(const Scenario& sc, const EngineSpec& engine,
                                      const cloth::Model& model,
                                      const std::vector<GrowthState>& states, double dt,
                                      const GrowthSearchOptions& o, long long* steps);

/// Searches the limit of engine (its integrator set) from dt_start. A search past
/// o.max_seconds stops before its next time step, keeps the bracket it has (stable_dt a lower
/// bound, first_unstable_dt an upper one) and says so in the cause. Throws Interrupted when
/// asked to stop, std::invalid_argument for a perturbation below cloth::kMinPerturbation.
GrowthLimit search_growth_limit(const Scenario& sc, const EngineSpec& engine,
                                const std::vector<GrowthState>& states, double dt_start,
                                const GrowthSearchOptions& o);

/// The linearised spring energy of a mode u (3 by #P) at positions x, by spring kind
/// (structural, shear, bend), as fractions of their sum: 1/2 k (d . (u_a - u_b))^2 per spring,
/// d its unit direction at x. NaN when the sum is 0.
std::array<double, 3> mode_energy_by_kind(const cloth::Model& model, const cloth::Matrix3X& x,
                                          const cloth::Matrix3X& u);

}  // namespace clothbench
