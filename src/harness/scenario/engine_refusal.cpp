#include "harness/scenario/engine_refusal.hpp"

#include <stdexcept>

#include "harness/io/user_error.hpp"
#include "reference/bullet/bullet_deformable.hpp"
#include "reference/bullet/bullet_softbody.hpp"

namespace clothbench {

std::optional<reference::Refusal> engine_refusal(const EngineSpec& spec,
                                                 const cloth::Scene& scene) {
  switch (spec.kind) {
    case EngineKind::custom:
      return std::nullopt;
    case EngineKind::bullet_deformable:
      return reference::deformable_refusal(spec.bullet, scene);
    case EngineKind::bullet_softbody:
      return reference::softbody_refusal(spec.bullet, spec.dt, scene);
  }
  throw std::logic_error("engine_refusal: an engine kind without a case");
}

void require_engine_can_model(const EngineSpec& spec, const cloth::Scene& scene,
                              const std::string& context) {
  if (const auto refusal = engine_refusal(spec, scene))
    throw UserError("engine " + spec.name + (context.empty() ? "" : " " + context) + ": " +
                    refusal->why);
}

}  // namespace clothbench
