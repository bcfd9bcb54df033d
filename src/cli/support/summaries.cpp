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

std::string stability_summary(const std::vector<StabilityRow>& rows) {
  std::ostringstream out;
  out << "engine,integrator,stable_dt,first_unstable_dt,predicted_dt,ratio\n";
  for (const StabilityRow& r : rows) {
    // "none": no stable dt found, or no failure up to --dt-max (the ratio is then left out)
    out << r.engine << ',' << r.integrator << ','
        << (std::isfinite(r.stable_dt) ? format_double(r.stable_dt) : "none") << ','
        << (std::isfinite(r.first_unstable_dt) ? format_double(r.first_unstable_dt) : "none") << ','
        << (std::isnan(r.predicted_dt) ? "" : format_double(r.predicted_dt)) << ','
        << (std::isfinite(r.ratio) ? format_double(std::round(r.ratio * 1000) / 1000) : "") << '\n';
  }
  return out.str();
}

std::string map_summary(const std::vector<VariedKey>& varied, const std::vector<MapRow>& rows) {
  std::ostringstream out;
  std::string header;
  for (const VariedKey& k : varied) header += k.key + ",";
  const std::string stability_columns = stability_summary({});
  out << header << stability_columns;
  for (const MapRow& r : rows) {
    std::string line = stability_summary({r.stability}).substr(stability_columns.size());
    for (auto v = r.values.rbegin(); v != r.values.rend(); ++v) line = csv_field(*v) + "," + line;
    out << line;
  }
  return out.str();
}

}  // namespace clothbench
