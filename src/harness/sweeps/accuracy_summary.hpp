#pragma once
/// @file accuracy_summary.hpp
/// The text `clothbench accuracy` prints on stdout.

#include <string>

#include "harness/sweeps/accuracy_rows.hpp"

namespace clothbench {

/// A short text summary for stdout: the references, each configuration's fitted order and
/// best error, and the recommendations (saying so when nothing meets the tolerance).
std::string accuracy_summary(const AccuracyReport& report);

}  // namespace clothbench
