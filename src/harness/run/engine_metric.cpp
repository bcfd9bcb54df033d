#include "harness/run/engine_metric.hpp"

#include <algorithm>
#include <cmath>

#include "cloth/model/triangle_mesh.hpp"
#include "harness/fabric/bias_metrics.hpp"
#include "harness/fabric/drape_metrics.hpp"
#include "harness/fabric/tensile_metrics.hpp"

namespace clothbench {

namespace {

/// The model run's engine was measured in: its own scene's when its overrides give one (its
/// springs and masses), kept in own; else the result's.
const cloth::Model& engine_model(const RunResult& result, const EngineRun& run, cloth::Model& own) {
  if (!run.spec.scene) return result.model;
  own = cloth::build_model(*run.spec.scene);
  return own;
}

/// The [test]'s metrics of one engine's final state x (a settled one, or the rest shape for
/// the names alone).
std::vector<TestMetric> test_rows(const RunResult& result, const EngineRun& run,
                                  const cloth::Matrix3X& x) {
  const Scenario& sc = result.scenario;
  cloth::Model own;
  const cloth::Model& model = engine_model(result, run, own);
  if (sc.test.kind == "drape") {
    // the support's axis through the held particles' centroid
    cloth::Vector3 centre = cloth::Vector3::Zero();
    int held = 0;
    for (size_t p = 0; p < sc.scene.held.size(); ++p)
      if (sc.scene.held[p]) {
        centre += x.col(Eigen::Index(p));
        ++held;
      }
    const DrapeProfile profile =
        drape_profile(x, model.triangles, centre / std::max(held, 1), sc.scene.gravity);
    return drape_rows(profile, final_drape_coefficient(result, run));
  }
  const double area = sc.scene.mesh ? cloth::mesh_area(*sc.scene.mesh)
                                    : sc.scene.cloth.size_u * sc.scene.cloth.size_v;
  return cantilever_rows(cantilever_metrics(model.x0, sc.scene.held, x, sc.scene.gravity,
                                            model.mass.sum() / area, sc.test.edge));
}

}  // namespace

std::vector<TensilePoint> strip_tensile_curve(const RunResult& result, const EngineRun& run) {
  const Scenario& sc = result.scenario;
  if (sc.test.kind != "strip-tensile") return {};
  if (run.spec.kind != EngineKind::custom || run.positions.size() != run.frames.size()) return {};
  const cloth::ClothParams& c = sc.scene.cloth;
  const bool along_u = sc.test.direction == "u";
  const cloth::Vector3 axis = along_u                       ? cloth::Vector3::UnitX()
                              : c.plane == cloth::Plane::xy ? cloth::Vector3::UnitY()
                                                            : cloth::Vector3::UnitZ();
  const cloth::Handle& handle = sc.scene.handles.at(0);
  const TensileSetup setup = tensile_setup(result.model.x0, sc.scene.held, handle.particles, axis,
                                           along_u ? c.size_v : c.size_u);
  // the springs the engine ran: its own with overrides
  cloth::Model own;
  const cloth::Model& model = engine_model(result, run, own);
  std::vector<double> t;
  std::vector<cloth::Matrix3X> x;
  for (size_t k = 0; k < run.frames.size() && run.frames[k].stable; ++k) {
    t.push_back(run.frames[k].t);
    x.push_back(run.positions[k]);
  }
  return tensile_curve(model.springs, model.x0, setup, handle.motion, t, x);
}

std::vector<BiasPoint> bias_extension_curve(const RunResult& result, const EngineRun& run) {
  const Scenario& sc = result.scenario;
  if (sc.test.kind != "bias-extension" || run.positions.size() != run.frames.size()) return {};
  const cloth::Vector3 across =
      sc.mesh.shape.plane == cloth::Plane::xy ? cloth::Vector3::UnitY() : cloth::Vector3::UnitZ();
  const cloth::Handle& handle = sc.scene.handles.at(0);
  const BiasSetup setup =
      bias_setup(result.model.x0, sc.scene.held, handle.particles, cloth::Vector3::UnitX(), across);
  // the springs the engine ran: its own with overrides
  cloth::Model own;
  const cloth::Model& model = engine_model(result, run, own);
  std::vector<double> t;
  std::vector<cloth::Matrix3X> x;
  for (size_t k = 0; k < run.frames.size() && run.frames[k].stable; ++k) {
    t.push_back(run.frames[k].t);
    x.push_back(run.positions[k]);
  }
  std::vector<BiasPoint> curve = bias_curve(model.springs, model.x0, setup, handle.motion, t, x);
  // another engine's forces are not the scene's springs: its angles alone
  if (run.spec.kind != EngineKind::custom)
    for (BiasPoint& p : curve) p.force = p.shear_force = p.shear_force_pin = NAN;
  return curve;
}

std::vector<TestMetric> test_metrics(const RunResult& result, const EngineRun& run) {
  if (result.scenario.test.kind.empty()) return {};
  if (result.scenario.test.kind == "bias-extension")
    return bias_rows(bias_extension_curve(result, run), result.scenario.test.fit_angle);
  // a strip-tensile's from its curve up to a blow-up, if any
  if (result.scenario.test.kind == "strip-tensile")
    return tensile_rows(strip_tensile_curve(result, run), result.scenario.test.fit_strain);
  // an unsettled run's rows name the metrics with empty values
  const bool settled = run.stable && !run.snapshots.empty();
  std::vector<TestMetric> rows =
      test_rows(result, run, settled ? run.snapshots.back() : result.model.x0);
  for (TestMetric& row : rows)
    if (!settled || !std::isfinite(row.value)) row.value = NAN;
  // the standard's overhang, from the engine's sequence of settles
  for (size_t i = 0; i < result.overhangs.size() && i < result.runs.size(); ++i)
    if (&result.runs[i] == &run || result.runs[i].spec.name == run.spec.name)
      for (const TestMetric& row : standard_rows(result.overhangs[i])) rows.push_back(row);
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
  if (s.test.kind == "cantilever" && s.test.overhang_rule == "standard")
    for (const TestMetric& row : standard_rows(OverhangSequence{})) names.push_back(row.metric);
  if (s.test.kind == "strip-tensile")
    for (const TestMetric& row : tensile_rows({}, s.test.fit_strain)) names.push_back(row.metric);
  if (s.test.kind == "bias-extension")
    for (const TestMetric& row : bias_rows({}, s.test.fit_angle)) names.push_back(row.metric);
  if (s.test.kind == "drape") {
    DrapeProfile flat;
    flat.radius.assign(kDrapeProfileBins, 0.0);
    for (const TestMetric& row : drape_rows(flat, NAN)) names.push_back(row.metric);
  }
  const bool listed = std::find(names.begin(), names.end(), "drape_coefficient") != names.end();
  if (!listed && (has_support(s) || !s.scene.shapes.cylinders.empty()))
    names.push_back("drape_coefficient");
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
