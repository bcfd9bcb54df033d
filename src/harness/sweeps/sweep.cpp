#include "harness/sweeps/sweep.hpp"

#include <cstdio>

#include "harness/io/csv_writer.hpp"

namespace clothbench {

EngineSpec with_integrator_and_dt(const EngineSpec& e, std::optional<cloth::Integrator> integrator,
                                  double dt) {
  EngineSpec out = e;
  out.dt = dt;
  if (e.kind == EngineKind::custom && integrator) out.solver.integrator = *integrator;
  // progress lines say what runs, not only whose engine it was made from
  char step[32];
  std::snprintf(step, sizeof step, "dt = %.3g s", dt);
  const bool swapped =
      e.kind == EngineKind::custom && integrator && *integrator != e.solver.integrator;
  out.label = e.name + " (" +
              (swapped ? std::string(cloth::integrator_name(*integrator)) + ", " : std::string()) +
              step + ")";
  return out;
}

std::string integrator_label(std::optional<cloth::Integrator> integrator) {
  return integrator ? cloth::integrator_name(*integrator) : "";
}

std::string budget_line(const Scenario& sc) {
  if (!(sc.max_run_seconds > 0)) return "";
  return "# --max-run-seconds " + format_double(sc.max_run_seconds) +
         ": the wall-clock budget of every engine run of this sweep (not a scenario key)\n";
}

std::string rerun_overrides(const EngineSpec& e) {
  std::string s;
  if (e.kind == EngineKind::custom)
    s += "--set engine." + e.name + ".integrator=" + cloth::integrator_name(e.solver.integrator) +
         " ";
  s += "--set engine." + e.name + ".dt=" + format_double(e.dt);
  return s;
}

}  // namespace clothbench
