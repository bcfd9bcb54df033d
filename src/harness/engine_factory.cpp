#include "harness/engine_factory.hpp"

#include <stdexcept>

#include "cloth/mass_spring_cloth.hpp"
#include "harness/user_error.hpp"
#include "reference/bullet_deformable.hpp"
#include "reference/bullet_softbody.hpp"

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

std::unique_ptr<cloth::Simulator> make_engine(const EngineSpec& spec, const cloth::Scene& scene) {
  switch (spec.kind) {
    case EngineKind::custom:
      return std::make_unique<cloth::MassSpringCloth>(scene, spec.solver);
    case EngineKind::bullet_deformable:
      return reference::make_bullet_deformable(spec.bullet, scene);
    case EngineKind::bullet_softbody:
      return reference::make_bullet_softbody(spec.bullet, spec.dt, scene);
  }
  throw std::logic_error("make_engine: an engine kind without a case");
}

}  // namespace clothbench
