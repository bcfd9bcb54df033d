#pragma once
/// @file gate_report.hpp
/// The gate table of `clothbench check` for machines: a JUnit XML report (the format GitHub
/// Actions, GitLab and Jenkins display: one test suite per scenario, one test case per gate)
/// and the same table as JSON for scripts.

#include <string>
#include <vector>

#include "harness/gate/regression_check.hpp"

namespace clothbench {

/// How long the check of one scenario took (the JUnit suite's time).
struct ScenarioTiming {
  std::string scenario;
  double seconds = 0;  // s of wall time for the scenario's runs and comparisons
};

/// The gates as a JUnit XML document: <testsuites> with one <testsuite> per scenario (in the
/// order of first appearance), one <testcase> per gate (name "engine quantity", classname
/// "clothbench.check.SCENARIO"), a <failure> with baseline, now and allowed for a failed gate
/// and <skipped> for a gate that is not gated. Attributes tests, failures, errors (always 0:
/// an error stops check with exit 2 before any report), skipped and time on every suite.
std::string junit_xml(const std::vector<Gate>& gates, const std::vector<ScenarioTiming>& timings);

/// The gates as JSON: {"gates": [{scenario, engine, quantity, baseline, now, difference,
/// allowed, allowed_text, gated, pass, note}...], "passed", "failed", "not_gated"}; non-finite
/// numbers are written as null.
std::string gates_json(const std::vector<Gate>& gates);

}  // namespace clothbench
