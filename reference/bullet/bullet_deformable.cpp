#include "reference/bullet/bullet_deformable.hpp"

#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableGravityForce.h>
#include <BulletSoftBody/btDeformableMassSpringForce.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cloth/model/triangle_mesh.hpp"
#include "format/number_format.hpp"
#include "reference/bullet/bullet_cloth.hpp"
#include "reference/bullet/repulsion_order.hpp"

namespace clothbench::reference {

namespace {

constexpr const char* kDeformableKind = "bullet-deformable";

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
    if (scene.cloth.self_collision) turn_on_self_collision(o, scene);
    m_face_tree_flags = btSoftBody::fCollision::SDF_RD;
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
    // the step's node and face contacts with rigid bodies and its self-contacts (all cleared
    // as the next step begins); there are no self-contacts with self-collision off
    return m_body->m_nodeRigidContacts.size() > 0 || m_body->m_faceRigidContacts.size() > 0 ||
           m_body->m_faceNodeContacts.size() > 0;
  }
  void reset_world(double t) override { m_spheres->place_at(t); }

  /// Bullet's vertex-face self-collision (see make_bullet_deformable).
  void turn_on_self_collision(const BulletOptions& o, const cloth::Scene& scene) {
    // both switches: VF_DD routes the body's own pair to CollideFF_DD, and only when
    // m_useSelfCollision is set (btSoftBody.cpp:4198-4249)
    m_body->m_cfg.collisions |= btSoftBody::fCollision::VF_DD;
    m_body->setSelfCollision(true);
    // the repulsion; setSpringStiffness also writes every link material's kLST, which only the
    // classic solver reads (btDeformableMassSpringForce.h:111 reads its own stiffness)
    m_body->setSpringStiffness(o.repulsion_stiffness);
    // equal to the colliders' margin when there are colliders (deformable_refusal checks)
    m_body->getCollisionShape()->setMargin(self_collision_margin(o, scene));
    // the repulsions' shuffled order from Bullet's initial state, whatever ran before
    reset_repulsion_order();
    // the face tree and its normal-cone copy are built by Bullet's first step, as SDF_RD is
    // on and building the body set m_bUpdateRtCst (btDeformableBodySolver.cpp:428-436)
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

/// True when every triangle reaches every other through triangles sharing an edge (none or
/// one triangle included).
bool edge_connected(const std::vector<cloth::Triangle>& triangles) {
  const int n = static_cast<int>(triangles.size());
  std::vector<int> root(static_cast<size_t>(n));
  std::iota(root.begin(), root.end(), 0);
  const auto find = [&](int t) {
    while (root[size_t(t)] != t) t = root[size_t(t)] = root[size_t(root[size_t(t)])];
    return t;
  };
  // join the triangles of each edge
  std::map<std::pair<int, int>, int> first;
  int parts = n;
  for (int t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[size_t(t)][size_t(k)], b = triangles[size_t(t)][size_t((k + 1) % 3)];
      const auto [it, fresh] = first.emplace(std::minmax(a, b), t);
      if (fresh) continue;
      const int ra = find(t), rb = find(it->second);
      if (ra == rb) continue;
      root[size_t(ra)] = rb;
      --parts;
    }
  return parts <= 1;
}

/// What self-collision needs of the options and the scene (with it on), or nullopt.
std::optional<Refusal> self_collision_refusal(const BulletOptions& o, const cloth::Scene& scene) {
  const std::string who = std::string(kDeformableKind) + ": ";
  if (!(o.repulsion_stiffness >= 0.0) || !std::isfinite(o.repulsion_stiffness))
    return Refusal{who + "repulsion_stiffness must be finite and not negative, got " +
                       cloth::toml_double(o.repulsion_stiffness) + " N/m",
                   {},
                   {"repulsion_stiffness"}};
  if (!(o.collision_margin >= 0.0) || !std::isfinite(o.collision_margin))
    return Refusal{who + "collision_margin must be finite and not negative, got " +
                       cloth::toml_double(o.collision_margin) + " m",
                   {},
                   {"collision_margin"}};
  if (!scene.cloth.self_collision) return std::nullopt;
  const double margin = self_collision_margin(o, scene);
  if (!(margin > 0.0) || !std::isfinite(margin))
    return Refusal{who + "self-collision needs a positive margin: cloth.thickness is " +
                       cloth::toml_double(scene.cloth.thickness) +
                       " m and collision_margin is 0 (give either a positive value)",
                   {"cloth.thickness"},
                   {"collision_margin"}};
  // one btCollisionShape margin serves both: rigid contacts and, doubled, self-contacts
  const cloth::Scene& s = scene;
  const bool has_colliders = !s.spheres.empty() || !s.shapes.planes.empty() ||
                             !s.shapes.boxes.empty() || !s.shapes.capsules.empty() ||
                             !s.shapes.cylinders.empty();
  if (has_colliders && margin != collider_margin(scene))
    return Refusal{
        who +
            "self-collision and collider contact share the soft body's one collision margin, "
            "but the colliders' margin is " +
            cloth::toml_double(collider_margin(scene)) + " m and self-collision needs " +
            cloth::toml_double(margin) +
            " m (collision_margin, or half of cloth.thickness when it is 0); make them equal "
            "(cloth.thickness = twice the colliders' margin, or collision_margin = the "
            "colliders' margin), or turn self-collision off for this engine",
        {"cloth.thickness", "cloth.self_collision"},
        {"collision_margin", "self_collision"}};
  return std::nullopt;
}

}  // namespace

double self_collision_margin(const BulletOptions& options, const cloth::Scene& scene) {
  return options.collision_margin > 0.0 ? options.collision_margin : 0.5 * scene.cloth.thickness;
}

std::optional<Refusal> deformable_refusal(const BulletOptions& o, const cloth::Scene& scene) {
  if (auto refusal = bullet_scene_refusal(scene, kDeformableKind)) return refusal;
  // Bullet 3.24 builds the face tree (initializeFaceTree, on the first step because SDF_RD is
  // on) by merging faces that share an edge until one node is left (buildTreeBottomUp,
  // btSoftBody.cpp:29-124): with two or more edge-connected pieces that loop never ends
  if (scene.mesh && !edge_connected(scene.mesh->triangles))
    return Refusal{std::string(kDeformableKind) +
                       " cannot model this mesh: its triangles are not one piece joined by "
                       "shared edges, and Bullet 3.24's deformable body then never finishes "
                       "building its face tree (the first step hangs); join the pieces or run "
                       "this scene on other engines",
                   {"cloth.mesh"},
                   {}};
  const cloth::ClothParams& c = scene.cloth;
  // btDeformableMassSpringForce has one elastic stiffness for every non-bending link
  // (a grid one particle wide has no shear springs, whatever their stiffness)
  const bool has_shear = c.k_shear > 0 && c.nu > 1 && c.nv > 1;
  // measured with Bullet 3.24: with no elastic link its solver never finishes a first step
  // (explicit and implicit alike, bend links or not, 15 s and counting, Ctrl-C unheard)
  if (!(c.k_structural > 0) && !has_shear)
    return Refusal{std::string(kDeformableKind) +
                       " cannot model this scene: the cloth has no structural or shear springs, "
                       "and Bullet's deformable solver never finishes a step without them (give "
                       "cloth.stiffness a structural or shear stiffness, or run this scene on "
                       "other engines)",
                   {"cloth.stiffness.structural", "cloth.stiffness.shear", "cloth.stiffness"},
                   {}};
  if (c.k_structural > 0 && has_shear && c.k_structural != c.k_shear)
    return Refusal{
        std::string(kDeformableKind) +
            " cannot model this scene: its mass-spring force has one stiffness for structural "
            "and shear springs, but cloth.stiffness has structural = " +
            cloth::toml_double(c.k_structural) + " and shear = " + cloth::toml_double(c.k_shear) +
            " N/m (make them equal, or run this scene on other engines)",
        {"cloth.stiffness.structural", "cloth.stiffness.shear"},
        {}};
  if (o.line_search && !o.implicit)
    return Refusal{std::string(kDeformableKind) +
                       ": line_search only applies to the implicit scheme; set implicit = true or "
                       "line_search = false",
                   {},
                   {"line_search", "implicit"}};
  // without projection the constraints become Lagrange multipliers, but Bullet's Newton
  // loop solves with node-sized vectors while its matrix product writes the multiplier rows
  // after them (btDeformableBackwardEulerObjective::multiply); the seed scene goes unstable
  if (o.implicit && !o.projection)
    return Refusal{std::string(kDeformableKind) +
                       ": the implicit scheme needs projection = true (without it Bullet 3.24's "
                       "Newton solve writes its Lagrange-multiplier rows past the end of "
                       "node-sized vectors)",
                   {},
                   {"projection", "implicit"}};
  return self_collision_refusal(o, scene);
}

std::unique_ptr<cloth::Simulator> make_bullet_deformable(const BulletOptions& options,
                                                         const cloth::Scene& scene) {
  if (const auto refusal = deformable_refusal(options, scene))
    throw std::invalid_argument(refusal->why);
  return std::make_unique<BulletDeformableCloth>(options, scene);
}

}  // namespace clothbench::reference
