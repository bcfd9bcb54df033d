#include "harness/run/engine_metric.hpp"

#include <algorithm>
#include <cmath>

#include "cloth/model/triangle_mesh.hpp"

namespace clothbench {

std::vector<TestMetric> test_metrics(const RunResult& result, const EngineRun& run) {
  const Scenario& sc = result.scenario;
  if (sc.test.kind != "cantilever") return {};
  const cloth::Model& model = result.model;
  const double area = sc.scene.mesh ? cloth::mesh_area(*sc.scene.mesh)
                                    : sc.scene.cloth.size_u * sc.scene.cloth.size_v;
  const double areal_density = model.mass.sum() / area;
  CantileverMetrics m{};
  const bool settled = run.stable && !run.snapshots.empty();
  if (settled)
    m = cantilever_metrics(model.x0, sc.scene.held, run.snapshots.back(), sc.scene.gravity,
                           areal_density, sc.test.edge);
  std::vector<TestMetric> rows = cantilever_rows(m);
  for (TestMetric& row : rows)
    if (!settled || !std::isfinite(row.value)) row.value = NAN;
  return rows;
}

namespace {

/// True when s holds a disk (a grid's disk or a ball), the drape coefficient's support.
bool has_support(const Scenario& s) {
  return std::any_of(s.constraints.begin(), s.constraints.end(), [](const ConstraintSpec& c) {
    return c.select == "disk" || c.select == "within";
  });
}

}  // namespace

std::vector<std::string> metric_names(const Scenario& s) {
  std::vector<std::string> names;
  // the rows a [test] writes, whatever their values
  if (s.test.kind == "cantilever")
    for (const TestMetric& row : cantilever_rows(CantileverMetrics{})) names.push_back(row.metric);
  if (has_support(s) || !s.scene.shapes.cylinders.empty()) names.push_back("drape_coefficient");
  return names;
}

std::optional<double> engine_metric(const RunResult& result, const EngineRun& run,
                                    const std::string& name) {
  for (const TestMetric& row : test_metrics(result, run))
    if (row.metric == name) return row.value;
  if (name != "drape_coefficient") return std::nullopt;
  const auto names = metric_names(result.scenario);
  if (std::find(names.begin(), names.end(), name) == names.end()) return std::nullopt;
  return run.stable ? final_drape_coefficient(result, run) : NAN;
}

}  // namespace clothbench
