#pragma once
/// @file fabric_preset.hpp
/// [cloth] fabric = "name": a fabric's measured properties (harness/io/fabric_table.hpp) as
/// the spring constants of the scene's cloth at its resolution (docs/fabrics.md, "The mapping").
///
/// Grid (spacing hu, hv, diagonal d): structural springs k_s along u and v, shear springs k_d on
/// both diagonals, bend springs k_b two steps apart. For a homogeneous small strain e the
/// springs store, per area,
///   C_uu = (k_s + 4 k_b) hu / hv + 2 k_d hu^3 / (d^2 hv),  C_vv likewise with u and v swapped,
///   C_uv = G = 2 k_d hu hv / d^2,
/// so a strip pulled along u with free sides has tensile stiffness Y_u = C_uu - C_uv^2 / C_vv
/// (N/m, independent of the spacing when hu = hv). The mapping takes G from the fabric's shear
/// stiffness (k_d = G d^2 / (2 hu hv)) and solves for k_s so that (Y_u + Y_v) / 2 is the mean of
/// the warp and weft tensile stiffness (one structural constant for both directions).
/// Mesh (mean edge length h, one structural spring per edge, no shear springs): a lattice of
/// equilateral triangles has Y = 2 (k_s + 3 k_b) / sqrt(3) and G = 3 Y / 8, so k_s =
/// sqrt(3) Y / 2 - 3 k_b; the fabric's shear stiffness is not used.
/// Bending: bend_model = "hinge" takes B (mean of warp and weft) directly; bend springs get
/// k_b = 9 B c^2 / (hu hv)^2 (mesh: h^4), c = (B / (rho_A g))^(1/3), which equals a spring
/// sheet's energy to the plate's at curvature 1 / c only: approximate (bend springs are not a
/// plate; `clothbench fit` calibrates). Damping (fabric_damping): 10 % of critical for one
/// structural spring between two particles.

#include <array>
#include <string>

#include "cloth/model/scene.hpp"
#include "cloth/model/triangle_mesh.hpp"
#include "harness/io/fabric_table.hpp"

namespace clothbench {

/// The damping ratio the presets give a structural spring between two particles.
inline constexpr double kFabricDampingRatio = 0.1;
/// g (m/s^2) in the bending length c = (B / (rho_A g))^(1/3) of the bend-spring constant.
inline constexpr double kStandardGravity = 9.80665;

/// What a fabric sets on a cloth. Stretch springs only when the fabric has tensile data.
struct FabricSprings {
  bool has_stretch = false;       // tensile data given: k_structural (and k_shear) set
  double k_structural = 0.0;      // N/m
  double k_shear = 0.0;           // N/m, grids only
  double k_bend = 0.0;            // N/m, bend_model = "springs"; 0 for the hinge
  double bending_rigidity = 0.0;  // N m, the hinge model's B
  double particle_mass = 0.0;     // kg, a particle's mass at this resolution (for the damping)
  std::string warning;            // "" or why the fabric's stretch could not be matched
};

/// Damping (N s/m) at kFabricDampingRatio of one spring k_structural (N/m) between two
/// particles of mass particle_mass (kg): 0.2 sqrt(k m / 2).
double fabric_damping(double k_structural, double particle_mass);

/// The springs of a grid cloth c (its nu, nv, size_u, size_v; k_shear is kept when the fabric
/// has no shear data, k_structural when it has no tensile data) made of fabric
/// f at areal density rho (kg/m^2).
FabricSprings grid_fabric_springs(const Fabric& f, const cloth::ClothParams& c, double rho,
                                  bool hinge);

/// The springs of a mesh cloth made of fabric f at areal density rho (kg/m^2); isotropic: the
/// mean of warp and weft. k_structural is the scene's, used when f has no tensile data.
FabricSprings mesh_fabric_springs(const Fabric& f, const cloth::TriangleMesh& mesh,
                                  double k_structural, double rho, bool hinge);

/// Tensile stiffness per width (N/m) of a grid's springs along u and v for a uniaxial stress
/// (sides free), from the energy density above: {Y_u, Y_v}.
std::array<double, 2> grid_tensile_stiffness(double k_structural, double k_shear, double k_bend,
                                             double hu, double hv);

}  // namespace clothbench
