#include "harness/engines/engine_factory.hpp"

#include <stdexcept>

#include "harness/io/user_error.hpp"

#include "cloth/integrators/mass_spring_cloth.hpp"
#include "reference/bullet/bullet_deformable.hpp"
#include "reference/bullet/bullet_softbody.hpp"
#include "reference/external/external_engine.hpp"
#include "reference/mujoco/mujoco_cloth.hpp"

namespace clothbench {

std::unique_ptr<cloth::Simulator> make_engine(const EngineSpec& spec, const cloth::Scene& scene) {
  // each engine sees the cloth with its own self-collision setting
  cloth::Scene own = scene;
  own.cloth.self_collision = self_collision_of(spec, scene.cloth) == SelfCollision::on;
  switch (spec.kind) {
    case EngineKind::custom:
      return std::make_unique<cloth::MassSpringCloth>(own, spec.solver);
    case EngineKind::bullet_deformable:
      return reference::make_bullet_deformable(spec.bullet, own);
    case EngineKind::bullet_softbody:
      return reference::make_bullet_softbody(spec.bullet, spec.dt, own);
    case EngineKind::mujoco:
      return reference::make_mujoco_cloth(spec.mujoco, spec.dt, own);
    case EngineKind::external:
      if (!reference::external_allowed())
        throw UserError(reference::external_not_allowed_message(spec.name));
      return std::make_unique<reference::ExternalEngine>(spec.external, own, spec.dt);
  }
  throw std::logic_error("make_engine: an engine kind without a case");
}

}  // namespace clothbench
