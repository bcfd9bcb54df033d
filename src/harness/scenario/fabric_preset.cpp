#include "harness/scenario/fabric_preset.hpp"

#include <algorithm>
#include <cmath>

namespace clothbench {

namespace {

/// The bend-spring constant (N/m) whose sheet stores the plate's energy B k^2 / 2 at the
/// curvature k = 1 / c: a spring two steps of h long shortens by h^3 k^2 / 3 on a cylinder, so
/// a sheet of them stores k_b h^4 k^4 / 18 per area.
double bend_spring_constant(double bending_rigidity, double rho, double h_squared) {
  const double c = std::cbrt(bending_rigidity / (rho * kStandardGravity));
  return 9.0 * bending_rigidity * c * c / (h_squared * h_squared);
}

/// The k_s >= 0 at which the grid's mean uniaxial stiffness is target, by bisection (the mean
/// grows with k_s); 0 with a warning when the other springs alone are stiffer.
double solve_structural(double target, double k_shear, double k_bend, double hu, double hv,
                        std::string& warning) {
  const auto mean = [&](double ks) {
    const auto y = grid_tensile_stiffness(ks, k_shear, k_bend, hu, hv);
    return 0.5 * (y[0] + y[1]);
  };
  if (mean(0.0) >= target) {
    warning = "the shear and bend springs alone are stiffer in stretch than the fabric (" +
              std::to_string(mean(0.0)) + " N/m against " + std::to_string(target) +
              " N/m): structural springs set to 0";
    return 0.0;
  }
  double lo = 0.0, hi = std::max(1.0, target);
  while (mean(hi) < target) hi *= 2.0;
  // 200 halvings reach the last bit of a double
  for (int k = 0; k < 200 && hi - lo > 1e-14 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (mean(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Mean edge length (m) of a mesh.
double mean_edge_length(const cloth::TriangleMesh& mesh) {
  const cloth::MeshEdges e = cloth::mesh_edges(mesh);
  double sum = 0.0;
  for (const auto& [a, b] : e.edges) sum += (mesh.x.col(a) - mesh.x.col(b)).norm();
  return e.edges.empty() ? 0.0 : sum / static_cast<double>(e.edges.size());
}

}  // namespace

double fabric_damping(double k_structural, double particle_mass) {
  return 2.0 * kFabricDampingRatio * std::sqrt(std::max(k_structural, 0.0) * particle_mass / 2.0);
}

std::array<double, 2> grid_tensile_stiffness(double k_structural, double k_shear, double k_bend,
                                             double hu, double hv) {
  // energy density coefficients of a homogeneous small strain
  const double d2 = hu * hu + hv * hv;
  const double axial = k_structural + 4.0 * k_bend;
  const double cuu = axial * hu / hv + 2.0 * k_shear * hu * hu * hu / (d2 * hv);
  const double cvv = axial * hv / hu + 2.0 * k_shear * hv * hv * hv / (d2 * hu);
  const double cuv = 2.0 * k_shear * hu * hv / d2;
  // uniaxial stress: the other direction contracts freely
  return {cuu - cuv * cuv / cvv, cvv - cuv * cuv / cuu};
}

FabricSprings grid_fabric_springs(const Fabric& f, const cloth::ClothParams& c, double rho,
                                  bool hinge) {
  // a direction with one particle has no springs: take the other's spacing
  const double hu0 = c.nu > 1 ? c.size_u / (c.nu - 1) : 0.0;
  const double hv0 = c.nv > 1 ? c.size_v / (c.nv - 1) : 0.0;
  const double hu = hu0 > 0 ? hu0 : hv0;
  const double hv = hv0 > 0 ? hv0 : hu0;
  FabricSprings s;
  s.bending_rigidity = hinge ? f.bending_mean() : 0.0;
  s.k_bend = hinge ? 0.0 : bend_spring_constant(f.bending_mean(), rho, hu * hv);
  s.k_structural = c.k_structural;
  s.k_shear =
      f.shear_stiffness ? *f.shear_stiffness * (hu * hu + hv * hv) / (2.0 * hu * hv) : c.k_shear;
  if (const auto y = f.tensile_mean()) {
    s.has_stretch = true;
    s.k_structural = solve_structural(*y, s.k_shear, s.k_bend, hu, hv, s.warning);
  }
  s.particle_mass = rho * hu * hv;
  return s;
}

FabricSprings mesh_fabric_springs(const Fabric& f, const cloth::TriangleMesh& mesh,
                                  double k_structural, double rho, bool hinge) {
  const double h = mean_edge_length(mesh);
  FabricSprings s;
  s.bending_rigidity = hinge ? f.bending_mean() : 0.0;
  s.k_bend = hinge || h <= 0 ? 0.0 : bend_spring_constant(f.bending_mean(), rho, h * h);
  s.k_structural = k_structural;
  if (const auto y = f.tensile_mean()) {
    s.has_stretch = true;
    // the equilateral lattice: Y = 2 (k_s + 3 k_b) / sqrt(3)
    s.k_structural = std::sqrt(3.0) / 2.0 * *y - 3.0 * s.k_bend;
    if (s.k_structural < 0) {
      s.warning =
          "the bend springs alone are stiffer in stretch than the fabric: structural "
          "springs set to 0";
      s.k_structural = 0.0;
    }
  }
  s.particle_mass = rho * std::sqrt(3.0) / 2.0 * h * h;
  return s;
}

}  // namespace clothbench
