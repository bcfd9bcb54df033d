#pragma once
/// @file accuracy_recommendation.hpp
/// The cheapest configuration of an accuracy sweep that meets an error tolerance, counted in
/// force evaluations so that the answer does not depend on the machine.

#include <string>
#include <vector>

#include "harness/sweeps/accuracy_rows.hpp"

namespace clothbench {

/// A CG iteration's cost in force evaluations, with its share of the Newton iteration that
/// linearises the springs for it: implicit-Euler steps on the flag and the table (release
/// build, one job, median of three runs, dt = 0.2, 0.1 and 0.05 ms) cost 3.0 to 3.6 explicit
/// force evaluations per CG iteration beyond their one force evaluation.
constexpr double kCgIterationCost = 3.0;

/// The machine-independent cost of a custom-engine row in particle force evaluations:
/// (force_evals + kCgIterationCost * cg_iterations) * particles; NaN for a Bullet row (its
/// work is not counted).
double counted_work(const AccuracyRow& r);

/// Per engine (in order), then overall: the cheapest stable row within tolerance by the
/// member error, see accuracy_sweep.hpp for the ranking.
std::vector<Recommendation> recommend_all(const std::vector<AccuracyRow>& rows,
                                          const std::vector<std::string>& engines, double tolerance,
                                          double AccuracyRow::*error);

}  // namespace clothbench
