#include "harness/sweeps/accuracy_summary.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "cloth/model/integrator.hpp"
#include "format/number_format.hpp"
#include "harness/sweeps/accuracy_recommendation.hpp"

namespace clothbench {

namespace {

std::string short_double(double v) {
  if (!std::isfinite(v)) return v > 0 ? "inf" : "-";
  return cloth::significant(v, 3);
}

std::string config_name(const AccuracyRow& r) {
  return r.engine + (r.integrator.empty() ? "" : " " + r.integrator);
}

void summarise_recommendations(std::ostringstream& s, const std::vector<Recommendation>& recs,
                               double tolerance, const char* error_name, bool grid) {
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "\ncheapest %s within %s <= %s m (by counted work, force evaluations + %g x CG "
                "iterations; see --help):\n",
                grid ? "grid" : "configuration", error_name, short_double(tolerance).c_str(),
                kCgIterationCost);
  s << buf;
  for (const Recommendation& r : recs) {
    const bool overall = r.scope == "overall";
    const double err = grid ? r.row.error_final : r.row.error_max;
    // the engine is the scope's name unless the scope is overall
    std::string what = overall ? config_name(r.row) : r.row.integrator;
    if (grid) what += (what.empty() ? "" : " ") + std::to_string(r.row.particles) + " particles";
    what += (what.empty() ? "" : " ") + std::string("at dt = ") + short_double(r.row.dt) + " s";
    std::string line;
    if (r.found)
      line = what + ": " + error_name + " " + short_double(err) + " m, " +
             short_double(r.row.wall_s_per_sim_s) + " s per simulated s" +
             (r.row.integrator.empty()
                  ? std::string()
                  : ", " + short_double(counted_work(r.row)) + " particle force evaluations");
    else if (!r.row.engine.empty())
      line = "nothing meets the tolerance (most accurate: " + what + ", " + error_name + " " +
             short_double(err) + " m)";
    else
      line = "nothing meets the tolerance (no stable run)";
    std::snprintf(buf, sizeof buf, "  %-24s %s\n", overall ? "overall" : r.engine.c_str(),
                  line.c_str());
    s << buf;
  }
}

}  // namespace

std::string accuracy_summary(const AccuracyReport& report) {
  std::ostringstream s;
  char buf[400];
  s << "reference: " << report.reference.description;
  if (std::isfinite(report.reference.error_floor))
    s << "; its error floor " << short_double(report.reference.error_floor) << " m";
  s << "\n\n";
  std::snprintf(buf, sizeof buf, "%-24s %-17s %6s %7s %6s %12s %12s\n", "engine", "integrator",
                "order", "theory", "stable", "best_error", "at_dt");
  s << buf;
  for (const ConvergenceFit& f : report.convergence) {
    int stable = 0, total = 0;
    const AccuracyRow* best = nullptr;
    for (const AccuracyRow& r : report.rows) {
      if (r.engine != f.engine || r.integrator != f.integrator) continue;
      ++total;
      if (!r.stable) continue;
      ++stable;
      if (!best || r.error_max < best->error_max) best = &r;
    }
    const auto integrator = cloth::parse_integrator(f.integrator);
    const std::string theory =
        integrator ? std::to_string(cloth::integrator_order(*integrator)) : "";
    std::snprintf(buf, sizeof buf, "%-24s %-17s %6s %7s %6s %12s %12s\n", f.engine.c_str(),
                  f.integrator.empty() ? "-" : f.integrator.c_str(),
                  std::isnan(f.order) ? "-" : short_double(f.order).c_str(), theory.c_str(),
                  (std::to_string(stable) + "/" + std::to_string(total)).c_str(),
                  best ? short_double(best->error_max).c_str() : "-",
                  best ? short_double(best->dt).c_str() : "-");
    s << buf;
  }
  if (report.tolerance > 0)
    summarise_recommendations(s, report.recommendations, report.tolerance, "error_max", false);
  if (!report.resolution_reference.study.empty()) {
    s << "\nresolution reference: " << report.resolution_reference.description << "\n";
    std::snprintf(buf, sizeof buf, "%-24s %-17s %9s %10s %6s %12s\n", "engine", "integrator",
                  "particles", "dt", "stable", "error_final");
    s << buf;
    for (const AccuracyRow& r : report.resolution_rows) {
      std::snprintf(buf, sizeof buf, "%-24s %-17s %9d %10s %6s %12s\n", r.engine.c_str(),
                    r.integrator.empty() ? "-" : r.integrator.c_str(), r.particles,
                    short_double(r.dt).c_str(), r.stable ? "yes" : "no",
                    r.stable ? short_double(r.error_final).c_str() : "-");
      s << buf;
    }
    if (report.tolerance > 0)
      summarise_recommendations(s, report.resolution_recommendations, report.tolerance,
                                "error_final", true);
  }
  return s.str();
}

}  // namespace clothbench
