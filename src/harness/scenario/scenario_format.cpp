#include "harness/scenario/scenario_format.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "cloth/model/scene.hpp"
#include "cloth/solvers/solver_options.hpp"
#include "reference/bullet/bullet_options.hpp"
#include "reference/mujoco/mujoco_options.hpp"

namespace clothbench {

const Keys kTopKeys = {"name",
                       "description",
                       "duration",
                       "frame_interval",
                       "snapshot_interval",
                       "animation_interval",
                       "blowup_strain",
                       "blowup_energy",
                       "reference",
                       "gravity",
                       "cloth",
                       "constraint",
                       "sphere",
                       "engine",
                       "wind",
                       "plane",
                       "box",
                       "capsule",
                       "cylinder",
                       "handle",
                       "test"};
const Keys kClothKeys = {"particles",        "size",       "center",        "plane",
                         "particle_mass",    "total_mass", "areal_density", "stiffness",
                         "damping",          "air_drag",   "mesh",          "generate",
                         "self_collision",   "thickness",  "self_friction", "bend_model",
                         "bending_rigidity", "fabric"};
const Keys kBendModels = {"springs", "hinge"};
const Keys kGenerateKeys = {"shape",  "radius",      "inner_radius", "size",
                            "length", "edge_length", "seed",         "center",
                            "plane",  "lattice",     "lattice_angle"};
const Keys kLattices = {"triangular", "grid"};
const Keys kTestKeys = {"kind", "edge", "direction", "fit_strain", "overhang_rule", "fit_angle"};
const Keys kOverhangRules = {"fixed", "standard"};
const Keys kTensileDirections = {"u", "v"};
const Keys kTestKinds = {"cantilever", "drape", "strip-tensile", "bias-extension"};
const Keys kStiffnessKeys = {"structural", "shear", "bend", "structural_u", "structural_v"};
const Keys kConstraintKeys = {"select", "hold", "center", "radius", "list", "name", "min", "max"};
const Keys kSphereKeys = {"center",   "radius", "restitution", "friction",
                          "velocity", "margin", "path"};
const Keys kColliderKeys = {"restitution", "friction", "margin", "velocity", "path"};
const Keys kPlaneKeys = {"point", "normal"};
const Keys kBoxKeys = {"center", "half_extents"};
const Keys kCapsuleKeys = {"a", "b", "radius"};
const Keys kCylinderKeys = {"center", "radius", "height"};
const Keys kHandleKeys = {"select", "center", "radius", "list", "name", "min", "max", "path"};
const Keys kEngineCommonKeys = {"name", "kind", "dt", "self_collision", "overrides"};

namespace {

/// The names of values, in order.
template <class Value, class Name>
Keys names_of(const std::vector<Value>& values, Name name) {
  Keys k;
  for (const Value& v : values) k.push_back(name(v));
  return k;
}

}  // namespace

const Keys kPlanes =
    names_of(std::vector<cloth::Plane>{cloth::Plane::xz, cloth::Plane::xy}, plane_name);
const Keys kSelections = {"corners", "edge:u0", "edge:u1", "edge:v0", "edge:v1",
                          "disk",    "indices", "group",   "within",  "box"};
const Keys kShapes = names_of(cloth::all_mesh_shapes(), cloth::mesh_shape_name);
const Keys kSoftbodyStiffness =
    names_of(reference::all_softbody_stiffnesses(), reference::softbody_stiffness_name);
const Keys kMujocoIntegrators =
    names_of(reference::all_mujoco_integrators(), reference::mujoco_integrator_name);
const Keys kNewtonMethods = names_of(cloth::all_newton_methods(), cloth::newton_method_name);
const Keys kLinearSolvers = names_of(cloth::all_linear_solvers(), cloth::linear_solver_name);
const Keys kCgForcings = names_of(cloth::all_cg_forcings(), cloth::cg_forcing_name);
const Keys kContactModes = names_of(cloth::all_contact_modes(), cloth::contact_mode_name);

const char* plane_name(cloth::Plane p) {
  return p == cloth::Plane::xy ? "xy" : "xz";
}

std::optional<cloth::Plane> parse_plane(std::string_view name) {
  for (cloth::Plane p : {cloth::Plane::xz, cloth::Plane::xy})
    if (name == plane_name(p)) return p;
  return std::nullopt;
}

std::optional<cloth::MeshShape> parse_shape(std::string_view name) {
  for (cloth::MeshShape s : cloth::all_mesh_shapes())
    if (name == cloth::mesh_shape_name(s)) return s;
  return std::nullopt;
}

Keys shape_keys(cloth::MeshShape shape) {
  switch (shape) {
    case cloth::MeshShape::disk:
      return {"radius"};
    case cloth::MeshShape::annulus:
      return {"radius", "inner_radius"};
    case cloth::MeshShape::rectangle:
      return {"size"};
    case cloth::MeshShape::tube:
      return {"radius", "length"};
  }
  return {};
}

Keys engine_kind_names() {
  Keys k;
  for (const EngineKindInfo& info : engine_kind_table()) k.push_back(info.name);
  return k;
}

Keys integrator_names() {
  return names_of(cloth::all_integrators(), cloth::integrator_name);
}

Keys all_engine_keys() {
  Keys k = kEngineCommonKeys;
  for (const EngineKindInfo& info : engine_kind_table())
    k.insert(k.end(), info.keys.begin(), info.keys.end());
  return k;
}

bool contains(const Keys& keys, std::string_view k) {
  return std::find(keys.begin(), keys.end(), k) != keys.end();
}

std::string join(const Keys& keys, const char* quote) {
  std::string out;
  for (std::string_view k : keys) {
    if (!out.empty()) out += ", ";
    out += quote;
    out += k;
    out += quote;
  }
  return out;
}

bool whole_multiple(double big, double small) {
  const double r = big / small;
  const double n = std::round(r);
  return n >= 1 && std::abs(r - n) <= 1e-9 * r;
}

std::string hold_letters(std::uint8_t hold) {
  std::string s;
  if (hold & cloth::kHoldX) s += 'x';
  if (hold & cloth::kHoldY) s += 'y';
  if (hold & cloth::kHoldZ) s += 'z';
  return s;
}

std::uint8_t parse_hold(std::string_view s) {
  std::uint8_t bits = 0;
  for (char c : s) {
    const std::uint8_t bit = c == 'x'   ? cloth::kHoldX
                             : c == 'y' ? cloth::kHoldY
                             : c == 'z' ? cloth::kHoldZ
                                        : 0;
    if (bit == 0 || (bits & bit)) return 0;
    bits |= bit;
  }
  return bits;
}

bool valid_engine_name(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '+';
  });
}

bool valid_scenario_name(std::string_view s) {
  return !s.empty() && s.front() != '.' && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
  });
}

std::string derived_engine_name(EngineKind kind, cloth::Integrator integrator) {
  return kind == EngineKind::custom ? "custom-" + std::string(cloth::integrator_name(integrator))
                                    : engine_kind_name(kind);
}

}  // namespace clothbench
