#pragma once
/// @file scenario_format.hpp
/// The scenario file format: the keys of every table, the spellings of enumerated values,
/// and the naming and timing rules the loader, the --set overrides and the writer share.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cloth/model/integrator.hpp"
#include "cloth/model/mesh_generator.hpp"
#include "cloth/model/scene.hpp"
#include "harness/scenario/engine_kind.hpp"

namespace clothbench {

/// A list of key names or value spellings.
using Keys = std::vector<std::string_view>;

// the keys of each table of the file format
extern const Keys kTopKeys;
extern const Keys kClothKeys;
extern const Keys kStiffnessKeys;
/// Values of cloth.bend_model.
extern const Keys kBendModels;
extern const Keys kGenerateKeys;  // [cloth.generate]
extern const Keys kLattices;      // [cloth.generate] lattice
extern const Keys kConstraintKeys;
extern const Keys kSphereKeys;
extern const Keys kColliderKeys;  // keys every [[plane]], [[box]], [[capsule]], [[cylinder]] has
extern const Keys kPlaneKeys;     // ... and each shape's own
extern const Keys kBoxKeys;
extern const Keys kCapsuleKeys;
extern const Keys kCylinderKeys;
extern const Keys kHandleKeys;
extern const Keys kTestKeys;          // [test]
extern const Keys kEngineCommonKeys;  // keys every [[engine]] may have

// the values of the enumerated keys: each spelled once, beside its enum (cloth's integrators
// and solver options, the Bullet options, the engine kinds) or here (planes, contact modes,
// selections), and listed from there
extern const Keys kTensileDirections;  // [test] direction of a strip-tensile test
extern const Keys kOverhangRules;      // [test] overhang_rule of a cantilever test
extern const Keys kTestKinds;          // [test] kind, the ones not yet measured included
extern const Keys kPlanes;
extern const Keys kSelections;
extern const Keys kShapes;  // [cloth.generate] shape
extern const Keys kSoftbodyStiffness;
/// The mujoco engine's integrators.
extern const Keys kMujocoIntegrators;
extern const Keys kNewtonMethods;
extern const Keys kLinearSolvers;
extern const Keys kCgForcings;
extern const Keys kContactModes;

/// "xz" or "xy".
const char* plane_name(cloth::Plane p);
/// The plane with that name, if any.
std::optional<cloth::Plane> parse_plane(std::string_view name);
/// The shape with that name, if any.
std::optional<cloth::MeshShape> parse_shape(std::string_view name);
/// The size keys [cloth.generate] needs for a shape (radius, inner_radius, size, length).
Keys shape_keys(cloth::MeshShape shape);

/// The names of the engine kinds, in engine_kind_table() order.
Keys engine_kind_names();
/// The names of the custom engine's integrators.
Keys integrator_names();
/// Every key an [[engine]] may have, whatever its kind.
Keys all_engine_keys();
/// True when k is one of keys.
bool contains(const Keys& keys, std::string_view k);
/// keys separated by ", ", each between quote.
std::string join(const Keys& keys, const char* quote = "");

/// Most steps one engine may take over a scenario's duration, and most frames a run may log:
/// far beyond what a run can do in a day, far below where step counts overflow.
inline constexpr double kMaxSteps = 1e9;
inline constexpr double kMaxFrames = 1e7;
/// Largest xpbd substeps and xpbd or projective iterations per step.
inline constexpr int kMaxSolverIterations = 10000;

/// True when big is a whole multiple (at least 1) of small, to 1e-9 relative.
bool whole_multiple(double big, double small);
/// "xyz", "yz", ... for held-axis bits.
std::string hold_letters(std::uint8_t hold);
/// The axis bits of "xyz", "yz", ...; 0 for anything else (empty, repeated or other letters).
std::uint8_t parse_hold(std::string_view s);
/// Engine names label CSV rows and --set keys: no dots, commas or spaces.
bool valid_engine_name(std::string_view s);
/// Scenario names become output folder names.
bool valid_scenario_name(std::string_view s);
/// The name of an engine that has none: "custom-<integrator>" or its kind.
std::string derived_engine_name(EngineKind kind, cloth::Integrator integrator);

}  // namespace clothbench
