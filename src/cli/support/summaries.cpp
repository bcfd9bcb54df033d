/// @file summaries.cpp

#include "summaries.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "cloth/model/integrator.hpp"
#include "harness/io/csv_writer.hpp"

namespace clothbench {

std::string run_summary(const RunResult& result) {
  std::ostringstream out;
  out << "engine,integrator,dt,stable,us_per_step,max_energy_error,final_rms_vs_reference\n";
  for (size_t i = 0; i < result.runs.size(); ++i) {
    const EngineRun& r = result.runs[i];
    const double final_rms = final_divergence(result, i);  // NaN: undefined, written empty
    out << r.spec.name << ','
        << (engine_kind_info(r.spec.kind).has_integrators
                ? cloth::integrator_name(r.spec.solver.integrator)
                : engine_kind_name(r.spec.kind))
        << ',' << format_double(r.spec.dt) << ','
        << (r.stable      ? "yes"
            : r.timed_out ? "timeout"
                          : "no")
        << ','
        << format_double(
               std::round(1e7 * r.wall_s / std::max<double>(1, double(r.counters.steps))) / 10)
        << ',' << (std::isnan(r.max_energy_error) ? "" : format_double(r.max_energy_error)) << ','
        << (std::isnan(final_rms) ? std::string("") : format_double(final_rms)) << '\n';
  }
  return out.str();
}

namespace {

std::string limit_text(double dt) {
  return std::isfinite(dt) ? format_double(dt) : "none";
}

std::string ratio_text(double ratio) {
  return std::isfinite(ratio) ? format_double(std::round(ratio * 1000) / 1000) : "";
}

/// What sets a growth limit, in a word: contact, free, bound (nothing grew up to --dt-max),
/// non-smooth, or "" without a growth measurement; contact and free gain " near physics" when
/// the verdict is near the physical growth (kNearPhysicalFraction).
std::string growth_by(const StabilityRow& r) {
  const std::string& c = r.growth.cause;
  const std::string near =
      c.find("; near the physics:") != std::string::npos ? " near physics" : "";
  if (c.rfind("set by contact", 0) == 0) return "contact" + near;
  if (c.rfind("free", 0) == 0) return "free" + near;
  if (c.rfind("no growth", 0) == 0) return "bound";
  if (c.rfind("non-smooth", 0) == 0) return "non-smooth";
  return "";
}

}  // namespace

std::string stability_summary(const std::vector<StabilityRow>& rows, StabilityMethod method) {
  std::ostringstream out;
  const bool blowup = method != StabilityMethod::growth, growth = method != StabilityMethod::blowup;
  out << "engine,integrator";
  if (blowup) out << ",stable_dt,first_unstable_dt";
  out << ",predicted_dt";
  if (blowup) out << ",ratio";
  if (growth) out << ",growth_stable_dt,growth_first_unstable_dt,growth_ratio,growth_by";
  out << '\n';
  for (const StabilityRow& r : rows) {
    // "none": no stable dt found, or no failure up to --dt-max (the ratio is then left out)
    out << r.engine << ',' << r.integrator;
    if (blowup) out << ',' << limit_text(r.stable_dt) << ',' << limit_text(r.first_unstable_dt);
    out << ',' << (std::isnan(r.predicted_dt) ? "" : format_double(r.predicted_dt));
    if (blowup) out << ',' << ratio_text(r.ratio);
    if (growth)
      out << ',' << limit_text(r.growth.stable_dt) << ',' << limit_text(r.growth.first_unstable_dt)
          << ',' << ratio_text(r.growth_ratio) << ',' << growth_by(r);
    out << '\n';
  }
  return out.str();
}

std::string map_summary(const std::vector<VariedKey>& varied, const std::vector<MapRow>& rows,
                        StabilityMethod method) {
  std::ostringstream out;
  std::string header;
  for (const VariedKey& k : varied) header += k.key + ",";
  const std::string stability_columns = stability_summary({}, method);
  out << header << stability_columns;
  for (const MapRow& r : rows) {
    std::string line = stability_summary({r.stability}, method).substr(stability_columns.size());
    for (auto v = r.values.rbegin(); v != r.values.rend(); ++v) line = csv_field(*v) + "," + line;
    out << line;
  }
  return out.str();
}

}  // namespace clothbench
