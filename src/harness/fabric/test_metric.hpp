#pragma once
/// @file test_metric.hpp
/// One measured value of a textile standard test: a row of tests.csv without its engine.

#include <string>

namespace clothbench {

/// One row of tests.csv (without the engine).
struct TestMetric {
  std::string metric;
  double value;  // NaN when undefined (written empty)
  std::string unit;
};

}  // namespace clothbench
