#include "harness/gate/run_figures.hpp"

#include <algorithm>
#include <cmath>

namespace clothbench {

std::map<std::string, double> run_metrics(const RunResult& r, size_t i) {
  const EngineRun& run = r.runs[i];
  const std::vector<Divergence>& d = r.divergence[i];
  double worst = 0;
  for (const Divergence& x : d) worst = std::max(worst, x.rms_distance);
  return {{"stable", run.stable ? 1.0 : 0.0},
          {"steps", double(run.counters.steps)},
          {"force_evals", double(run.counters.force_evals)},
          {"cg_iterations", double(run.counters.cg_iterations)},
          {"max_energy_error", run.max_energy_error},
          {"final_rms_vs_reference", final_divergence(r, i)},
          {"max_rms_vs_reference", d.empty() ? NAN : worst},
          {"drape_coefficient", final_drape_coefficient(r, run)},
          {"final_com_y", run.frames.back().com.y()}};
}

double shape_rms(const cloth::Matrix3X& a, const cloth::Matrix3X& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

}  // namespace clothbench
