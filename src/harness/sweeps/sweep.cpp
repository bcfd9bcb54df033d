#include "harness/sweeps/sweep.hpp"

#include <stdexcept>

#include "harness/io/csv_writer.hpp"

namespace clothbench {

EngineSpec with_integrator_and_dt(const EngineSpec& e, const std::string& integrator, double dt) {
  EngineSpec out = e;
  out.dt = dt;
  if (e.kind == EngineKind::custom && !integrator.empty()) {
    const auto i = cloth::parse_integrator(integrator);
    if (!i) throw std::invalid_argument("unknown integrator " + integrator);
    out.solver.integrator = *i;
  }
  return out;
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
