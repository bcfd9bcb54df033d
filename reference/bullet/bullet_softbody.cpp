#include "reference/bullet/bullet_softbody.hpp"

#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "format/number_format.hpp"
#include "reference/bullet/bullet_cloth.hpp"
#include "reference/bullet/link_stiffness.hpp"

namespace clothbench::reference {

namespace {

constexpr const char* kSoftbodyKind = "bullet-softbody";

/// One cloth in its own classic soft-rigid world.
class BulletSoftBodyCloth final : public BulletCloth {
 public:
  BulletSoftBodyCloth(const BulletOptions& o, double dt, const cloth::Scene& scene,
                      SoftbodySelfFlags flags)
      : BulletCloth(scene, Dissipation::energy_balance), m_options(o), m_dt(dt) {
    // the world; it creates and owns its default soft-body solver
    m_world = std::make_unique<btSoftRigidDynamicsWorld>(
        m_parts.dispatcher.get(), m_parts.broadphase.get(), &m_constraint_solver,
        m_parts.config.get());
    set_up_world(*m_world, m_world->getWorldInfo(), scene);

    // the cloth: one material per (spring constant, summed inverse mass) pair, so "matched"
    // can give every link the kLST of its own isolated link
    const cloth::VectorX im = m_model.inv_mass;
    btSoftBodyWorldInfo& info = m_world->getWorldInfo();
    m_body = build_soft_body(
        info, m_model, positions(), [&](btSoftBody& body, const cloth::SpringLink& s) {
          const bool pin_a = m_model.free.col(s.a).isZero(), pin_b = m_model.free.col(s.b).isZero();
          const double w = (pin_a ? 0.0 : im[s.a]) + (pin_b ? 0.0 : im[s.b]);
          const std::pair<double, double> key(s.stiffness, w);
          auto it = m_materials.find(key);
          if (it == m_materials.end()) it = m_materials.emplace(key, body.appendMaterial()).first;
          return it->second;
        });
    set_link_stiffness(m_dt);
    btSoftBody::Config& cfg = m_body->m_cfg;
    cfg.piterations = o.iterations;
    cfg.viterations = 0;
    cfg.diterations = 0;
    cfg.kDP = 0.0;  // no extra velocity damping: the projection alone
    cfg.collisions = btSoftBody::fCollision::SDF_RS;
    add_self_flags(flags);
    set_contact_config(*m_body, scene);
    m_face_tree_flags = btSoftBody::fCollision::VF_SS;
    m_world->addSoftBody(m_body);

    m_spheres = std::make_unique<ColliderBodies>(*m_world, scene);
  }

  ~BulletSoftBodyCloth() override {
    // the cloth leaves the world before it is freed; members then go in reverse order
    m_spheres.reset();
    m_world->removeSoftBody(m_body);
    delete m_body;
  }

 private:
  /// Sets every material's kLST for steps of dt.
  void set_link_stiffness(double dt) {
    for (auto& [key, material] : m_materials) {
      const auto [k, w] = key;
      if (m_options.stiffness == SoftbodyStiffness::klst)
        material->m_kLST = m_options.klst;
      else  // a link between two pins never moves: any kLST will do
        material->m_kLST = w > 0.0 ? matched_link_klst(k, w, dt, m_options.iterations) : 1.0;
      material->m_kAST = 1.0;
      material->m_kVST = 1.0;
    }
    m_dt = dt;
  }

  /// Adds Bullet's classic self-collision switches (none for the engine itself).
  void add_self_flags(SoftbodySelfFlags flags) {
    using F = btSoftBody::fCollision;
    if (flags == SoftbodySelfFlags::vf_ss) m_body->m_cfg.collisions |= F::VF_SS;
    if (flags == SoftbodySelfFlags::cl_ss || flags == SoftbodySelfFlags::cl_ss_self) {
      // a cluster per face; clusters that share a node never collide (btSoftBody.cpp:1683-1704)
      m_body->generateClusters(0);
      m_body->m_cfg.collisions |= F::CL_SS;
    }
    if (flags == SoftbodySelfFlags::cl_ss_self) m_body->m_cfg.collisions |= F::CL_SELF;
  }

  void advance(double dt) override {
    // "matched" depends on dt: follow a caller that changes it
    if (dt != m_dt && m_options.stiffness == SoftbodyStiffness::matched) {
      set_link_stiffness(dt);
      m_body->updateLinkConstants();
    }
    step_world(*m_world, m_world->getWorldInfo(), *m_spheres, time(), dt);
  }
  bool had_contact() const override { return m_body->m_rcontacts.size() > 0; }
  void reset_world(double t) override { m_spheres->place_at(t); }

  BulletOptions m_options;
  double m_dt;
  std::map<std::pair<double, double>, btSoftBody::Material*> m_materials;  // owned by m_body
  // declared in the order they are needed, so they are freed in reverse
  CollisionParts m_parts;
  btSequentialImpulseConstraintSolver m_constraint_solver;
  std::unique_ptr<btSoftRigidDynamicsWorld> m_world;
  std::unique_ptr<ColliderBodies> m_spheres;
};

}  // namespace

std::optional<Refusal> softbody_refusal(const BulletOptions& o, double dt,
                                        const cloth::Scene& scene) {
  if (auto refusal = bullet_scene_refusal(scene, kSoftbodyKind)) return refusal;
  const std::string who = std::string(kSoftbodyKind) + ": ";
  if (o.stiffness == SoftbodyStiffness::klst && !(o.klst > 0.0 && o.klst <= 1.0))
    return Refusal{who + "klst must be in (0, 1], got " + cloth::toml_double(o.klst), {}, {"klst"}};
  if (o.iterations < 1)
    return Refusal{who + "iterations must be at least 1, got " + std::to_string(o.iterations),
                   {},
                   {"iterations"}};
  if (!(dt > 0.0))
    return Refusal{who + "dt must be positive, got " + cloth::toml_double(dt), {}, {"dt"}};
  if (o.implicit || o.line_search)
    return Refusal{who + "implicit and line_search are bullet-deformable options",
                   {},
                   {"implicit", "line_search"}};
  // Bullet's classic friction is kDF * friction with kDF in [0, 1]
  return friction_above_one(scene, who);
}

std::unique_ptr<cloth::Simulator> make_bullet_softbody(const BulletOptions& options, double dt,
                                                       const cloth::Scene& scene) {
  return make_bullet_softbody_with_flags(options, dt, scene, SoftbodySelfFlags::none);
}

bool softbody_self_collision_available() {
  return false;
}

std::unique_ptr<cloth::Simulator> make_bullet_softbody_with_flags(const BulletOptions& options,
                                                                  double dt,
                                                                  const cloth::Scene& scene,
                                                                  SoftbodySelfFlags flags) {
  if (const auto refusal = softbody_refusal(options, dt, scene))
    throw std::invalid_argument(refusal->why);
  return std::make_unique<BulletSoftBodyCloth>(options, dt, scene, flags);
}

}  // namespace clothbench::reference
