#include "harness/run/attribution.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cloth/model/constants.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench {

namespace {

using cloth::kNaN;
constexpr const char* kNoScheme =
    "position-based dynamics: no custom time scheme matches it, so its distance is not split";

bool selected(const std::vector<std::string>& names, const std::string& name) {
  return names.empty() || std::find(names.begin(), names.end(), name) != names.end();
}

/// RMS over particles of |a - b| (m).
double rms(const cloth::Matrix3X& a, const cloth::Matrix3X& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

const EngineRun* find_run(const RunResult& result, const std::string& name) {
  for (const EngineRun& run : result.runs)
    if (run.spec.name == name) return &run;
  return nullptr;
}

/// Frames where all three runs are stable and logged positions.
size_t common_frames(const EngineRun& a, const EngineRun& b, const EngineRun& c) {
  size_t n = std::min({a.positions.size(), b.positions.size(), c.positions.size(), a.frames.size(),
                       b.frames.size(), c.frames.size()});
  for (size_t k = 0; k < n; ++k)
    if (!a.frames[k].stable || !b.frames[k].stable || !c.frames[k].stable) return k;
  return n;
}

/// The final and max rows of one Bullet engine with its matched engine.
void split_rows(const RunResult& result, const EngineRun& bullet, const EngineRun& matched,
                std::vector<AttributionRow>& rows) {
  const EngineRun& ref = result.runs[static_cast<size_t>(result.reference)];
  const size_t n = common_frames(bullet, matched, ref);
  AttributionRow last{bullet.spec.name, ref.spec.name, matched.spec.name, "final", 0, 0, 0, 0, ""};
  AttributionRow most = last;
  most.at = "max";
  if (n == 0) {
    last.total_rms = last.scheme_rms = last.model_rms = kNaN;
    most.total_rms = most.scheme_rms = most.model_rms = kNaN;
    last.note = most.note = "no frame where all three engines are stable";
  }
  for (size_t k = 0; k < n; ++k) {
    last.t = most.t = ref.frames[k].t;
    last.total_rms = rms(bullet.positions[k], ref.positions[k]);
    last.scheme_rms = rms(matched.positions[k], ref.positions[k]);
    last.model_rms = rms(matched.positions[k], bullet.positions[k]);
    most.total_rms = std::max(most.total_rms, last.total_rms);
    most.scheme_rms = std::max(most.scheme_rms, last.scheme_rms);
    most.model_rms = std::max(most.model_rms, last.model_rms);
  }
  const double end = result.scenario.duration;
  if (n > 0 && std::abs(last.t - end) > 1e-9 * std::max(1.0, end))
    last.note = most.note =
        "an engine was unstable: compared up to t = " + format_double(last.t) + " s";
  rows.push_back(last);
  rows.push_back(most);
}

/// The rows of bullet-softbody: its own distance, no split.
void unsplit_rows(const RunResult& result, size_t index, std::vector<AttributionRow>& rows) {
  const EngineRun& run = result.runs[index];
  const EngineRun& ref = result.runs[static_cast<size_t>(result.reference)];
  const std::vector<Divergence>& d = result.divergence[index];
  for (const char* at : {"final", "max"}) {
    AttributionRow row{run.spec.name, ref.spec.name, "", at, 0, kNaN, kNaN, kNaN, kNoScheme};
    for (const Divergence& x : d) {
      row.t = x.t;
      row.total_rms = std::string(at) == "max" && std::isfinite(row.total_rms)
                          ? std::max(row.total_rms, x.rms_distance)
                          : x.rms_distance;
    }
    rows.push_back(row);
  }
}

}  // namespace

std::string matched_engine_name(const std::string& bullet_name) {
  return "custom-as-" + bullet_name;
}

std::optional<EngineSpec> matched_engine(const EngineSpec& bullet) {
  if (bullet.kind != EngineKind::bullet_deformable) return std::nullopt;
  EngineSpec e;
  e.name = matched_engine_name(bullet.name);
  e.kind = EngineKind::custom;
  e.dt = bullet.dt;
  if (!bullet.bullet.implicit) {
    e.solver.integrator = cloth::Integrator::imex_euler;
    return e;
  }
  e.solver.integrator = cloth::Integrator::implicit_euler;
  e.solver.clamp_compressed = false;  // Bullet's elastic Jacobian is the full one
  if (bullet.bullet.line_search) {
    e.solver = cloth::line_search_options();
    e.solver.newton_iterations = 1;  // Bullet's m_maxNewtonIterations
    e.solver.clamp_compressed = false;
  }
  return e;
}

void add_matched_engines(Scenario& sc, std::vector<std::string>& names) {
  const std::vector<std::string> chosen = names;
  const size_t count = sc.engines.size();
  for (size_t i = 0; i < count; ++i) {
    const EngineSpec bullet = sc.engines[i];
    if (!selected(chosen, bullet.name)) continue;
    const std::optional<EngineSpec> m = matched_engine(bullet);
    if (!m) continue;
    const auto same = std::find_if(sc.engines.begin(), sc.engines.end(),
                                   [&](const EngineSpec& e) { return e.name == m->name; });
    if (same != sc.engines.end()) {
      // a scenario.toml written by --explain holds it already: run it as it is
      if (same->kind != EngineKind::custom || same->dt != m->dt ||
          same->solver.integrator != m->solver.integrator)
        throw UserError("--explain adds the engine " + m->name + " for " + bullet.name + ", but " +
                        sc.source + " has another engine of that name already (rename it)");
      if (!chosen.empty()) names.push_back(m->name);
      continue;
    }
    sc.engines.push_back(*m);
    if (!chosen.empty()) names.push_back(m->name);
  }
}

std::vector<AttributionRow> attribution(const RunResult& result) {
  std::vector<AttributionRow> rows;
  for (size_t i = 0; i < result.runs.size(); ++i) {
    const EngineRun& run = result.runs[i];
    if (!engine_kind_info(run.spec.kind).is_bullet) continue;
    if (!matched_engine(run.spec)) {
      unsplit_rows(result, i, rows);
      continue;
    }
    if (const EngineRun* m = find_run(result, matched_engine_name(run.spec.name)))
      split_rows(result, run, *m, rows);
  }
  return rows;
}

void write_attribution(const RunResult& result, const std::string& dir) {
  CsvWriter csv(dir + "/attribution.csv", output_header("attribution.csv"));
  for (const AttributionRow& r : attribution(result)) {
    csv.add(r.engine).add(r.reference).add(r.matched).add(r.at).add(r.t).add(r.total_rms);
    if (r.matched.empty())
      csv.skip().skip();
    else
      csv.add(r.scheme_rms).add(r.model_rms);
    csv.add(csv_field(r.note)).end_row();
  }
  csv.commit();
}

}  // namespace clothbench
