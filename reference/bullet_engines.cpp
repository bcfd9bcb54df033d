#include "reference/bullet_engines.hpp"

#include <stdexcept>

#include "reference/bullet_deformable.hpp"
#include "reference/bullet_softbody.hpp"

namespace clothbench::reference {

bool is_bullet_kind(const std::string& kind) {
  return kind == "bullet-deformable" || kind == "bullet-softbody";
}

std::unique_ptr<cloth::Simulator> make_bullet_engine(const EngineSpec& spec,
                                                     const cloth::Scene& scene) {
  if (spec.kind == "bullet-deformable") return make_bullet_deformable(spec.bullet, scene);
  if (spec.kind == "bullet-softbody") return make_bullet_softbody(spec.bullet, spec.dt, scene);
  throw std::invalid_argument("engine \"" + spec.name + "\": kind \"" + spec.kind +
                              "\" is not a Bullet engine (bullet-deformable, bullet-softbody)");
}

}  // namespace clothbench::reference
