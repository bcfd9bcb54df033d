#pragma once
/// @file engine_kind.hpp
/// The kinds of engine a scenario can run, with one table of their names and the facts the
/// harness, the gate and the report need about each (parsed once, at the edge).

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace clothbench {

/// One name each, used in scenario files, CSV and run.json.
enum class EngineKind {
  custom,             ///< the custom mass-spring cloth (src/cloth), with its integrators
  bullet_deformable,  ///< Bullet's deformable world with the mass-spring force
  bullet_softbody,    ///< Bullet's classic soft body, position-based link projection
  mujoco,             ///< MuJoCo 2.2.2: particles as slide-joint bodies, springs as tendons
  external            ///< the user's own program, by protocol (docs/external-engines.md)
};

/// What the harness knows about a kind of engine.
struct EngineKindInfo {
  EngineKind kind;
  const char* name;         // "custom", "bullet-deformable", "bullet-softbody"
  bool has_integrators;     // the integrator key chooses among cloth::Integrator
  bool is_bullet;           // built by reference/bullet/ (the only code that includes Bullet)
  bool energy_gated;        // energy_error measures the time scheme (has a spring damper)
  const char* energy_note;  // why the energy error is not gated ("" when it is)
  std::vector<std::string_view> keys;  // the kind's own [[engine]] keys
};

/// The kinds, in the order above.
const std::vector<EngineKindInfo>& engine_kind_table();
/// The table's row of kind.
const EngineKindInfo& engine_kind_info(EngineKind kind);
/// "custom", "bullet-deformable", "bullet-softbody", "mujoco" or "external".
const char* engine_kind_name(EngineKind kind);
/// The kind with that name, if any.
std::optional<EngineKind> parse_engine_kind(std::string_view name);

}  // namespace clothbench
