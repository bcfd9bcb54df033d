#pragma once
/// @file run_figures.hpp
/// The figures of a run that a baseline records and compares: one engine's metrics.csv
/// quantities, and the RMS distance between two shapes.

#include <map>
#include <string>

#include "cloth/model/types.hpp"
#include "harness/run/runner.hpp"

namespace clothbench {

/// The quantities metrics.csv records for engine i of r, by name (tolerances_file.hpp's
/// kMetricQuantities).
std::map<std::string, double> run_metrics(const RunResult& r, size_t i);

/// RMS over particles of the distance between two shapes, 3 by #P each (m).
double shape_rms(const cloth::Matrix3X& a, const cloth::Matrix3X& b);

}  // namespace clothbench
