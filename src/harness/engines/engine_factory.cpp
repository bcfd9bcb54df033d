#include "harness/engines/engine_factory.hpp"

#include <stdexcept>

#include "cloth/integrators/mass_spring_cloth.hpp"
#include "reference/bullet/bullet_deformable.hpp"
#include "reference/bullet/bullet_softbody.hpp"

namespace clothbench {

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
