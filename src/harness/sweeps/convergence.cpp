#include "harness/sweeps/convergence.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clothbench {

double fitted_order(const std::vector<double>& dts, const std::vector<double>& errors) {
  const size_t n = std::min(dts.size(), errors.size());
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < n; ++i) {
    const double lx = std::log(dts[i]), ly = std::log(errors[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  const double den = double(n) * sxx - sx * sx;
  return den > 0 ? (double(n) * sxy - sx * sy) / den : std::numeric_limits<double>::quiet_NaN();
}

std::vector<ConvergenceFit> fit_convergence(const std::vector<AccuracyRow>& rows,
                                            double error_floor) {
  std::vector<ConvergenceFit> fits;
  for (size_t i = 0; i < rows.size();) {
    ConvergenceFit fit;
    fit.engine = rows[i].engine;
    fit.integrator = rows[i].integrator;
    std::vector<double> dts, errors;
    for (; i < rows.size() && rows[i].engine == fit.engine && rows[i].integrator == fit.integrator;
         ++i) {
      const AccuracyRow& r = rows[i];
      const bool above_floor = std::isnan(error_floor) || r.error_final > error_floor;
      if (r.stable && std::isfinite(r.error_final) && r.error_final > 0 && above_floor) {
        dts.push_back(r.dt);
        errors.push_back(r.error_final);
      }
    }
    fit.points = static_cast<int>(dts.size());
    fit.order = fitted_order(dts, errors);
    fits.push_back(fit);
  }
  return fits;
}

}  // namespace clothbench
