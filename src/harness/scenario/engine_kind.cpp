#include "harness/scenario/engine_kind.hpp"

#include <stdexcept>

namespace clothbench {

const std::vector<EngineKindInfo>& engine_kind_table() {
  static const std::vector<EngineKindInfo> table = {
      {EngineKind::custom,
       "custom",
       true,
       false,
       true,
       "",
       {"integrator", "newton", "newton_iterations", "newton_tolerance", "linear_solver",
        "cg_tolerance", "cg_max_iterations", "cg_forcing", "contacts", "clamp_compressed",
        "clamped_iterations", "substeps", "iterations"}},
      {EngineKind::bullet_deformable,
       "bullet-deformable",
       false,
       true,
       true,
       "",
       {"implicit", "line_search", "projection", "repulsion_stiffness", "collision_margin"}},
      // no spring damper: the projection dissipates, and the adapter books each step's energy
      // balance as dissipated, so the energy error is 0 by construction
      {EngineKind::bullet_softbody,
       "bullet-softbody",
       false,
       true,
       false,
       "0 by construction (bullet-softbody books its energy balance as dissipated)",
       {"stiffness", "klst", "iterations"}},
      // tendon dampers booked at the new state's power, as bullet-deformable's
      {EngineKind::mujoco,
       "mujoco",
       false,
       false,
       true,
       "",
       {"integrator", "margin", "friction", "solref", "solimp", "cone"}},
      // its dampers are the program's: the harness books what the program reports
      {EngineKind::external,
       "external",
       false,
       false,
       false,
       "not gated (an external engine books its own dissipation, which the harness cannot check)",
       {"command", "step_timeout", "share_cpu"}}};
  return table;
}

const EngineKindInfo& engine_kind_info(EngineKind kind) {
  for (const EngineKindInfo& info : engine_kind_table())
    if (info.kind == kind) return info;
  throw std::logic_error("engine_kind_info: a kind missing from the table");
}

const char* engine_kind_name(EngineKind kind) {
  return engine_kind_info(kind).name;
}

std::optional<EngineKind> parse_engine_kind(std::string_view name) {
  for (const EngineKindInfo& info : engine_kind_table())
    if (name == info.name) return info.kind;
  return std::nullopt;
}

}  // namespace clothbench
