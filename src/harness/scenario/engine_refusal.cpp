#include "harness/scenario/engine_refusal.hpp"

#include <stdexcept>

#include "cloth/model/integrator.hpp"
#include "format/number_format.hpp"
#include "harness/io/user_error.hpp"
#include "reference/bullet/bullet_deformable.hpp"
#include "reference/bullet/bullet_softbody.hpp"
#include "reference/mujoco/mujoco_refusal.hpp"

namespace clothbench {

const char* const kSoftbodyNoSelfCollision =
    "bullet-softbody cannot keep a cloth's layers apart: Bullet 3.24's classic soft body tests "
    "vertex-face contact only between two bodies, and its cluster self-collision flag turns "
    "soft-soft collision off; set self_collision = false here, or leave it out (a cloth's "
    "self_collision = true is then noted as not available for this engine)";

const char* const kMujocoNoSelfCollision =
    "mujoco cannot keep a cloth's layers apart: the adapter excludes particle-particle contacts "
    "(contype 1, conaffinity 0), since MuJoCo 2.2.2 would need a geom pair per particle pair; "
    "set self_collision = false here, or leave it out (a cloth's self_collision = true is then "
    "noted as not available for this engine)";

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
  const bool has = spec.kind != EngineKind::bullet_softbody && spec.kind != EngineKind::mujoco;
  return has ? SelfCollision::on : SelfCollision::not_available;
}

namespace {

/// contacts = "barrier" is inelastic: a collider that bounces is refused.
std::optional<reference::Refusal> barrier_refusal(const cloth::Scene& scene) {
  std::optional<reference::Refusal> refusal;
  auto check = [&](const auto& colliders, const char* table) {
    for (size_t k = 0; k < colliders.size() && !refusal; ++k) {
      const cloth::Collider& c = colliders[k];
      if (c.restitution == 0.0) continue;
      const std::string key = std::string(table) + "." + std::to_string(k);
      refusal = reference::Refusal{
          std::string("contacts = \"barrier\" models inelastic contact, but ") + key +
              " has restitution " + cloth::shortest_decimal(c.restitution) +
              " (the barrier is line-search's default): set it to 0, or name contacts = "
              "\"in-solve\" or \"after-step\"",
          {key + ".restitution"},
          {"contacts"}};
    }
  };
  check(scene.spheres, "sphere");
  check(scene.shapes.planes, "plane");
  check(scene.shapes.boxes, "box");
  check(scene.shapes.capsules, "capsule");
  check(scene.shapes.cylinders, "cylinder");
  return refusal;
}

}  // namespace

std::optional<reference::Refusal> engine_refusal(const EngineSpec& spec,
                                                 const cloth::Scene& scene) {
  // the Bullet engines bend with springs only; which spring stiffness matches a rigidity is
  // what a calibration finds, so none is made up here
  if (spec.kind != EngineKind::custom && scene.cloth.bend_model == cloth::BendModel::hinge)
    return reference::Refusal{std::string(engine_kind_name(spec.kind)) +
                                  " bends with springs only and cannot model bend_model = "
                                  "\"hinge\": run it on a copy of the scene with bend_model = "
                                  "\"springs\" and cloth.stiffness.bend",
                              {"cloth.bend_model", "cloth.bending_rigidity"},
                              {}};
  // the other engines read one structural stiffness; a calibration would be needed to make
  // theirs differ by direction, so none is made up here
  if (spec.kind != EngineKind::custom && scene.cloth.anisotropic() && !scene.mesh)
    return reference::Refusal{std::string(engine_kind_name(spec.kind)) +
                                  " has one structural stiffness for both grid directions and "
                                  "cannot model cloth.stiffness structural_u != structural_v: "
                                  "run it on a copy of the scene with structural alone",
                              {"cloth.stiffness.structural_u", "cloth.stiffness.structural_v"},
                              {}};
  switch (spec.kind) {
    case EngineKind::custom: {
      // xpbd and projective work on springs alone: a constraint per spring, a spring per
      // projection; the hinge model's form is neither
      const cloth::Integrator i = spec.solver.integrator;
      if (scene.cloth.bend_model == cloth::BendModel::hinge &&
          (i == cloth::Integrator::xpbd || i == cloth::Integrator::projective))
        return reference::Refusal{std::string("the custom engine's ") + cloth::integrator_name(i) +
                                      " integrator works on springs alone and cannot model "
                                      "bend_model = \"hinge\": choose another integrator, or "
                                      "bend_model = \"springs\"",
                                  {"cloth.bend_model"},
                                  {"integrator"}};
      if (i == cloth::Integrator::implicit_euler &&
          spec.solver.contacts == cloth::ContactMode::barrier)
        return barrier_refusal(scene);
      return std::nullopt;
    }
    case EngineKind::bullet_deformable: {
      // the engine sees the cloth with its own self-collision setting
      cloth::Scene own = scene;
      own.cloth.self_collision = self_collision_of(spec, scene.cloth) == SelfCollision::on;
      return reference::deformable_refusal(spec.bullet, own);
    }
    case EngineKind::bullet_softbody:
      if (spec.self_collision.value_or(false))
        return reference::Refusal{kSoftbodyNoSelfCollision, {}, {"self_collision"}};
      return reference::softbody_refusal(spec.bullet, spec.dt, scene);
    case EngineKind::mujoco: {
      if (spec.self_collision.value_or(false))
        return reference::Refusal{kMujocoNoSelfCollision, {}, {"self_collision"}};
      cloth::Scene own = scene;
      own.cloth.self_collision = false;
      return reference::mujoco_refusal(spec.mujoco, own);
    }
    case EngineKind::external:
      // protocol version 1 carries no self-contact
      if (self_collision_of(spec, scene.cloth) == SelfCollision::on)
        return reference::Refusal{
            "self-collision is not available on external engines (protocol version 1 carries no "
            "self-contact); set self_collision = false on the engine",
            {"cloth.self_collision"},
            {"self_collision"}};
      return std::nullopt;
  }
  throw std::logic_error("engine_refusal: an engine kind without a case");
}

void require_engine_can_model(const EngineSpec& spec, const cloth::Scene& scene,
                              const std::string& context) {
  if (spec.kind == EngineKind::external && !reference::external_allowed())
    throw UserError(reference::external_not_allowed_message(spec.name));
  if (const auto refusal = engine_refusal(spec, scene))
    throw UserError("engine " + spec.name + (context.empty() ? "" : " " + context) + ": " +
                    refusal->why);
}

}  // namespace clothbench
