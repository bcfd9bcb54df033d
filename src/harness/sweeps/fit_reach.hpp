#pragma once
/// @file fit_reach.hpp
/// Targets that no parameter can make a scenario show, found before any run: a cantilever's
/// bending length c is measured through the heavy elastica only while the chord angle stays
/// below 83.9 degrees (overhang l <= 6 c, elastica.hpp), so a target c below l / 6 (or a
/// flexural rigidity below rho_A g (l / 6)^3) has no value at any stiffness.

#include <optional>
#include <string>

#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// The overhang l (m) of cantilever scenario s: the rest distance along x from its last held
/// column at or below [test] edge to its tip. NaN for another test or without such columns.
double cantilever_overhang(const Scenario& s);

/// Why scenario s cannot show metric at target within tolerance (absolute) at any parameter,
/// or nothing when it can (or the harness cannot tell). The reason names the limit and what to
/// change, for a person.
std::optional<std::string> unmeasurable_target(const std::string& metric, double target,
                                               double tolerance, const Scenario& s);

}  // namespace clothbench
