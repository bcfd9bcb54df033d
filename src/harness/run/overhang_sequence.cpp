#include "harness/run/overhang_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "cloth/model/constants.hpp"
#include "harness/fabric/cantilever_metrics.hpp"

namespace clothbench {

namespace {

using cloth::kPi;
constexpr double kSameColumn = 1e-9;  // m: rest x within this is one column

/// The chord angle (deg) of positions x (3 by #P, m) with the platform held up to edge.
double chord_degrees(const cloth::Matrix3X& x0, const std::vector<std::uint8_t>& held,
                     const cloth::Matrix3X& x, const cloth::Vector3& gravity, double edge) {
  // the areal density only scales the flexural rigidity, not the angle
  return cantilever_metrics(x0, held, x, gravity, 1.0, edge).chord_angle * 180.0 / kPi;
}

/// Measures one settle: the chord angle at the end and its change over the last tenth.
OverhangRun measure(const cloth::Matrix3X& x0, const std::vector<std::uint8_t>& held,
                    const EngineRun& run, const cloth::Vector3& gravity, double edge) {
  OverhangRun out;
  out.edge = edge;
  out.overhang = x0.row(0).maxCoeff() - edge;
  out.chord_angle = out.settle_change = NAN;
  if (!run.stable || run.snapshots.empty()) return out;
  // the end, and nine tenths of the way: a kept frame, else the snapshot before the last
  const cloth::Matrix3X* before = nullptr;
  if (run.positions.size() == run.frames.size() && run.positions.size() >= 2)
    before = &run.positions[size_t(std::lround(0.9 * double(run.positions.size() - 1)))];
  else if (run.snapshots.size() >= 2)
    before = &run.snapshots[run.snapshots.size() - 2];
  out.chord_angle = chord_degrees(x0, held, run.snapshots.back(), gravity, edge);
  if (before) out.settle_change = out.chord_angle - chord_degrees(x0, held, *before, gravity, edge);
  out.settled = std::abs(out.settle_change) <= kSettledChordChange;
  return out;
}

/// held with the platform ending at edge: every particle at rest x <= edge held on every axis,
/// none of the old platform beyond it.
std::vector<std::uint8_t> platform_to(const cloth::Matrix3X& x0,
                                      const std::vector<std::uint8_t>& held, double old_edge,
                                      double edge) {
  std::vector<std::uint8_t> out = held;
  for (Eigen::Index p = 0; p < x0.cols(); ++p) {
    if (x0(0, p) <= edge + kSameColumn)
      out[size_t(p)] = cloth::kHoldAll;
    else if (x0(0, p) <= old_edge + kSameColumn)
      out[size_t(p)] = 0;
  }
  return out;
}

}  // namespace

OverhangCandidates overhang_candidates(const cloth::Matrix3X& x0) {
  // the columns' rest x, increasing
  std::vector<double> xs(size_t(x0.cols()));
  for (Eigen::Index p = 0; p < x0.cols(); ++p) xs[size_t(p)] = x0(0, p);
  std::sort(xs.begin(), xs.end());
  std::vector<double> columns;
  for (double x : xs)
    if (columns.empty() || x > columns.back() + kSameColumn) columns.push_back(x);
  // clamp columns from the tip's neighbour back to the second column
  OverhangCandidates out;
  if (columns.size() < 3) return out;
  for (size_t k = columns.size() - 2; k >= 1; --k) {
    out.edge.push_back(columns[k]);
    out.overhang.push_back(columns.back() - columns[k]);
  }
  return out;
}

OverhangSequence standard_overhang_sequence(const Scenario& sc, const cloth::Model& model,
                                            const EngineRun& run) {
  const cloth::Matrix3X& x0 = model.x0;
  const OverhangCandidates c = overhang_candidates(x0);
  // the scene's own clamp: the last column at or below its edge
  size_t first = c.edge.empty() ? 0 : c.edge.size() - 1;
  for (size_t k = 0; k < c.edge.size(); ++k)
    if (c.edge[k] <= sc.test.edge + kSameColumn) {
      first = k;
      break;
    }
  const bool own_first = !c.edge.empty() && c.edge[first] <= sc.test.edge + kSameColumn;
  const cloth::Vector3 g = sc.scene.gravity;
  auto settle = [&](size_t k) {
    const double edge = c.edge[k];
    // the scene's own overhang: its run is already there
    if (k == first && own_first) return measure(x0, sc.scene.held, run, g, edge);
    const std::vector<std::uint8_t> held = platform_to(x0, sc.scene.held, sc.test.edge, edge);
    // the scene with the platform moved, for the engine's own scene too
    Scenario moved = sc;
    moved.scene.held = held;
    moved.test.edge = edge;
    EngineSpec spec = run.spec;
    if (spec.scene) {
      auto own = std::make_shared<cloth::Scene>(*spec.scene);
      own->held = platform_to(x0, own->held, sc.test.edge, edge);
      spec.scene = own;
    }
    const cloth::Model m = cloth::build_model(moved.scene);
    const EngineRun settled = run_engine(moved, spec, m, nullptr, true);
    return measure(x0, held, settled, g, edge);
  };
  if (c.edge.empty()) {
    OverhangSequence none;
    none.overhang = none.bending_length = NAN;
    return none;
  }
  return find_standard_overhang(c.overhang, first, settle);
}

}  // namespace clothbench
