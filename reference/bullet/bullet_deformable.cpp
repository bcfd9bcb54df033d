#include "reference/bullet/bullet_deformable.hpp"

#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableGravityForce.h>
#include <BulletSoftBody/btDeformableMassSpringForce.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>

#include <stdexcept>
#include <string>

#include "format/number_format.hpp"
#include "reference/bullet/bullet_cloth.hpp"

namespace clothbench::reference {

namespace {

constexpr const char* kKind = "bullet-deformable";

/// One cloth in its own deformable world.
class BulletDeformableCloth final : public BulletCloth {
 public:
  BulletDeformableCloth(const BulletOptions& o, const cloth::Scene& scene)
      : BulletCloth(scene, Dissipation::damper_power) {
    // the world, wired the way Bullet's deformable demos wire it
    m_body_solver = std::make_unique<btDeformableBodySolver>();
    m_constraint_solver = std::make_unique<btDeformableMultiBodyConstraintSolver>();
    m_constraint_solver->setDeformableSolver(m_body_solver.get());
    m_world = std::make_unique<btDeformableMultiBodyDynamicsWorld>(
        m_parts.dispatcher.get(), m_parts.broadphase.get(), m_constraint_solver.get(),
        m_parts.config.get(), m_body_solver.get());
    m_world->setImplicit(o.implicit);
    m_world->setLineSearch(o.line_search);
    m_world->setUseProjection(o.projection);
    set_up_world(*m_world, m_world->getWorldInfo(), scene);

    // the cloth: our nodes and links; the force, not the material, holds the stiffness
    m_body = build_soft_body(m_world->getWorldInfo(), m_model, positions(),
                             [](btSoftBody&, const cloth::SpringLink&) { return nullptr; });
    // nodes against rigid bodies, as ours: SDF_RD alone collides nothing, SDF_RDN adds nodes
    m_body->m_cfg.collisions = btSoftBody::fCollision::SDF_RD | btSoftBody::fCollision::SDF_RDN;
    m_body->m_cfg.drag = 0.0;
    set_contact_config(*m_body, scene);
    m_world->addSoftBody(m_body);

    // forces: the report's springs (damping along the spring) and gravity, which the world's
    // gravity does not apply to deformable nodes
    const cloth::ClothParams& c = scene.cloth;
    const double k = c.k_structural > 0 ? c.k_structural : c.k_shear;
    m_springs = std::make_unique<btDeformableMassSpringForce>(k, c.damping, true, c.k_bend);
    m_gravity = std::make_unique<btDeformableGravityForce>(to_bt(scene.gravity));
    m_world->addForce(m_body, m_springs.get());
    m_world->addForce(m_body, m_gravity.get());

    m_spheres = std::make_unique<ColliderBodies>(*m_world, scene);
  }

  ~BulletDeformableCloth() override {
    // the cloth leaves the world before it is freed; members then go in reverse order
    m_spheres.reset();
    m_world->removeSoftBody(m_body);
    delete m_body;
  }

 private:
  void advance(double dt) override {
    step_world(*m_world, m_world->getWorldInfo(), *m_spheres, time(), dt);
  }
  bool had_contact() const override {
    // the step's node and face contacts with rigid bodies (cleared as the next step begins)
    return m_body->m_nodeRigidContacts.size() > 0 || m_body->m_faceRigidContacts.size() > 0;
  }

  // declared in the order they are needed, so they are freed in reverse
  CollisionParts m_parts;
  std::unique_ptr<btDeformableBodySolver> m_body_solver;
  std::unique_ptr<btDeformableMultiBodyConstraintSolver> m_constraint_solver;
  std::unique_ptr<btDeformableMultiBodyDynamicsWorld> m_world;
  std::unique_ptr<btDeformableMassSpringForce> m_springs;
  std::unique_ptr<btDeformableGravityForce> m_gravity;
  std::unique_ptr<ColliderBodies> m_spheres;
};

}  // namespace

std::optional<Refusal> deformable_refusal(const BulletOptions& o, const cloth::Scene& scene) {
  if (auto refusal = bullet_scene_refusal(scene, kKind)) return refusal;
  const cloth::ClothParams& c = scene.cloth;
  // btDeformableMassSpringForce has one elastic stiffness for every non-bending link
  // (a grid one particle wide has no shear springs, whatever their stiffness)
  const bool has_shear = c.k_shear > 0 && c.nu > 1 && c.nv > 1;
  // measured with Bullet 3.24: with no elastic link its solver never finishes a first step
  // (explicit and implicit alike, bend links or not, 15 s and counting, Ctrl-C unheard)
  if (!(c.k_structural > 0) && !has_shear)
    return Refusal{std::string(kKind) +
                       " cannot model this scene: the cloth has no structural or shear springs, "
                       "and Bullet's deformable solver never finishes a step without them (give "
                       "cloth.stiffness a structural or shear stiffness, or run this scene on "
                       "other engines)",
                   {"cloth.stiffness.structural", "cloth.stiffness.shear", "cloth.stiffness"},
                   {}};
  if (c.k_structural > 0 && has_shear && c.k_structural != c.k_shear)
    return Refusal{
        std::string(kKind) +
            " cannot model this scene: its mass-spring force has one stiffness for structural "
            "and shear springs, but cloth.stiffness has structural = " +
            cloth::toml_double(c.k_structural) + " and shear = " + cloth::toml_double(c.k_shear) +
            " N/m (make them equal, or run this scene on other engines)",
        {"cloth.stiffness.structural", "cloth.stiffness.shear"},
        {}};
  if (o.line_search && !o.implicit)
    return Refusal{std::string(kKind) +
                       ": line_search only applies to the implicit scheme; set implicit = true or "
                       "line_search = false",
                   {},
                   {"line_search", "implicit"}};
  // without projection the constraints become Lagrange multipliers, but Bullet's Newton
  // loop solves with node-sized vectors while its matrix product writes the multiplier rows
  // after them (btDeformableBackwardEulerObjective::multiply); the seed scene goes unstable
  if (o.implicit && !o.projection)
    return Refusal{std::string(kKind) +
                       ": the implicit scheme needs projection = true (without it Bullet 3.24's "
                       "Newton solve writes its Lagrange-multiplier rows past the end of "
                       "node-sized vectors)",
                   {},
                   {"projection", "implicit"}};
  return std::nullopt;
}

std::unique_ptr<cloth::Simulator> make_bullet_deformable(const BulletOptions& options,
                                                         const cloth::Scene& scene) {
  if (const auto refusal = deformable_refusal(options, scene))
    throw std::invalid_argument(refusal->why);
  return std::make_unique<BulletDeformableCloth>(options, scene);
}

}  // namespace clothbench::reference
