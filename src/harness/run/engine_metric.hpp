#pragma once
/// @file engine_metric.hpp
/// One engine's scalar results by name, from wherever a run keeps them: the [test]'s metrics
/// (tests.csv) and the drape coefficient (summary.csv), so that a caller (clothbench fit) needs
/// only the metric's name.

#include <optional>
#include <string>
#include <vector>

#include "harness/fabric/bias_metrics.hpp"
#include "harness/fabric/cantilever_metrics.hpp"
#include "harness/fabric/tensile_metrics.hpp"
#include "harness/run/runner.hpp"

namespace clothbench {

/// The strip-tensile curve of run (its stable frames, whose positions it needs kept); none for
/// another test, or for an engine whose forces are not the scene's springs (every engine but
/// the custom one).
std::vector<TensilePoint> strip_tensile_curve(const RunResult& result, const EngineRun& run);

/// The bias-extension curve of run (its stable frames, whose positions it needs kept); none
/// for another test. Every engine's angles; force and shear force NaN for an engine whose
/// forces are not the scene's springs (every engine but the custom one).
std::vector<BiasPoint> bias_extension_curve(const RunResult& result, const EngineRun& run);

/// The [test]'s metrics of run's final state (cantilever: cantilever_rows, drape: drape_rows;
/// strip-tensile: tensile_rows of its curve; bias-extension: bias_rows of its curve),
/// as tests.csv has them (empty for a scenario without a [test]); values NaN when the run did
/// not end stable (its final shape is not a settled one) or the metric is undefined.
std::vector<TestMetric> test_metrics(const RunResult& result, const EngineRun& run);

/// The names of the metrics a run of s gives: its [test]'s (cantilever, drape, strip-tensile,
/// bias-extension), and
/// drape_coefficient (summary.csv) when s has a support (a held disk or a cylinder).
std::vector<std::string> metric_names(const Scenario& s);

/// The metric called name of run: a [test] metric first, else drape_coefficient. NaN when the
/// run gives it no value; nullopt when runs of this scenario do not give it at all.
std::optional<double> engine_metric(const RunResult& result, const EngineRun& run,
                                    const std::string& name);

}  // namespace clothbench
