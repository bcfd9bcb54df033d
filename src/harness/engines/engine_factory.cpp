#include "harness/engines/engine_factory.hpp"

#include <stdexcept>

#include "cloth/integrators/mass_spring_cloth.hpp"
#include "reference/bullet/bullet_deformable.hpp"
#include "reference/bullet/bullet_softbody.hpp"

namespace clothbench {

const char* self_collision_name(SelfCollision s) {
  switch (s) {
    case SelfCollision::off:
      return "off";
    case SelfCollision::on:
      return "on";
    case SelfCollision::not_available:
      return "not available";
  }
  throw std::logic_error("self_collision_name: a value without a case");
}

SelfCollision self_collision_of(const EngineSpec& spec, const cloth::ClothParams& cloth) {
  if (!spec.self_collision.value_or(cloth.self_collision)) return SelfCollision::off;
  return spec.kind == EngineKind::bullet_softbody ? SelfCollision::not_available
                                                  : SelfCollision::on;
}

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
  }
  throw std::logic_error("make_engine: an engine kind without a case");
}

}  // namespace clothbench
