#include "harness/engine_factory.hpp"

#include <stdexcept>

#include "cloth/mass_spring_cloth.hpp"
#include "reference/bullet_engines.hpp"

namespace clothbench {

const std::vector<std::string>& engine_kinds() {
  static const std::vector<std::string> kinds = {"custom", "bullet-deformable", "bullet-softbody"};
  return kinds;
}

std::unique_ptr<cloth::Simulator> make_engine(const EngineSpec& spec, const cloth::Scene& scene) {
  if (spec.kind == "custom") return std::make_unique<cloth::MassSpringCloth>(scene, spec.solver);
  if (reference::is_bullet_kind(spec.kind)) return reference::make_bullet_engine(spec, scene);
  throw std::invalid_argument("engine " + spec.name + ": unknown kind \"" + spec.kind + "\"");
}

}  // namespace clothbench
