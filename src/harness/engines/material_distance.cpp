#include "harness/engines/material_distance.hpp"

#include <algorithm>
#include <cmath>

namespace clothbench {

cloth::Vector3 bilinear_position(const cloth::Matrix3X& x, int nu, int nv, double u, double v) {
  // the cell holding (u, v), the last cell for u = 1 or v = 1
  const auto cell = [](int n, double w, int& k, double& f) {
    if (n < 2) {
      k = 0;
      f = 0;
      return;
    }
    const double s = std::clamp(w, 0.0, 1.0) * (n - 1);
    k = std::min(static_cast<int>(std::floor(s)), n - 2);
    f = s - k;
  };
  int i = 0, j = 0;
  double fu = 0, fv = 0;
  cell(nu, u, i, fu);
  cell(nv, v, j, fv);
  const int i1 = std::min(i + 1, nu - 1), j1 = std::min(j + 1, nv - 1);
  return (1 - fu) * (1 - fv) * x.col(j * nu + i) + fu * (1 - fv) * x.col(j * nu + i1) +
         (1 - fu) * fv * x.col(j1 * nu + i) + fu * fv * x.col(j1 * nu + i1);
}

double material_rms_distance(const cloth::Matrix3X& a, int a_nu, int a_nv, const cloth::Matrix3X& b,
                             int b_nu, int b_nv) {
  double sum = 0;
  for (int j = 0; j < a_nv; ++j)
    for (int i = 0; i < a_nu; ++i) {
      const double u = a_nu > 1 ? double(i) / (a_nu - 1) : 0.0;
      const double v = a_nv > 1 ? double(j) / (a_nv - 1) : 0.0;
      sum += (a.col(j * a_nu + i) - bilinear_position(b, b_nu, b_nv, u, v)).squaredNorm();
    }
  return std::sqrt(sum / double(a_nu * a_nv));
}

}  // namespace clothbench
