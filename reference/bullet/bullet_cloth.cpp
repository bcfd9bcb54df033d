#include "reference/bullet/bullet_cloth.hpp"

#include <algorithm>
#include <stdexcept>

#include "cloth/contact/sphere_collision.hpp"
#include "cloth/forces/energies.hpp"
#include "cloth/forces/spring_forces.hpp"
#include "format/number_format.hpp"

namespace clothbench::reference {

namespace {

/// Every collider of scene with its key ("sphere.0", "box.1", ...) and its name in messages.
struct NamedCollider {
  std::string key;
  std::string name;
  const cloth::Collider* collider;
};

template <class Shape>
void name_all(const std::vector<Shape>& shapes, const char* kind, std::vector<NamedCollider>& out) {
  for (size_t i = 0; i < shapes.size(); ++i)
    out.push_back({std::string(kind) + "." + std::to_string(i),
                   std::string(kind) + " " + std::to_string(i), &shapes[i]});
}

std::vector<NamedCollider> named_colliders(const cloth::Scene& scene) {
  std::vector<NamedCollider> all;
  name_all(scene.spheres, "sphere", all);
  name_all(scene.shapes.planes, "plane", all);
  name_all(scene.shapes.boxes, "box", all);
  name_all(scene.shapes.capsules, "capsule", all);
  name_all(scene.shapes.cylinders, "cylinder", all);
  return all;
}

/// Restitution, margins: what no Bullet soft body's contact can honour.
std::optional<Refusal> collider_refusal(const cloth::Scene& scene, const std::string& who) {
  const std::vector<NamedCollider> all = named_colliders(scene);
  for (const NamedCollider& c : all) {
    const double margin = c.collider->margin;
    if (c.collider->restitution != 0.0)
      return Refusal{who + c.name + " has restitution " +
                         cloth::toml_double(c.collider->restitution) +
                         ", but Bullet's soft-body contacts are inelastic; expected 0",
                     {c.key + ".restitution"},
                     {}};
    if (margin != all.front().collider->margin)
      return Refusal{who + "colliders with different margins (" +
                         cloth::toml_double(all.front().collider->margin) + " m for " +
                         all.front().name + ", " + cloth::toml_double(margin) + " m for " + c.name +
                         "): a Bullet soft body has one contact margin",
                     {c.key + ".margin", all.front().key + ".margin"},
                     {}};
    if (!(margin > 0.0))
      return Refusal{who + c.name + " needs a positive contact margin, got " +
                         cloth::toml_double(margin) + " m",
                     {c.key + ".margin"},
                     {}};
  }
  return std::nullopt;
}

}  // namespace

std::optional<Refusal> friction_above_one(const cloth::Scene& scene, const std::string& who) {
  for (const NamedCollider& c : named_colliders(scene))
    if (c.collider->friction > 1.0)
      return Refusal{who + c.name + " has friction " + cloth::toml_double(c.collider->friction) +
                         ", but the classic soft body's friction is at most 1",
                     {c.key + ".friction"},
                     {}};
  return std::nullopt;
}

std::optional<Refusal> bullet_scene_refusal(const cloth::Scene& scene, const std::string& kind) {
  const std::string who = kind + ": ";
  if (scene.cloth.air_drag < 0.0)
    return Refusal{who + "air drag must not be negative, got " +
                       cloth::toml_double(scene.cloth.air_drag) + " N s/m",
                   {"cloth.air_drag"},
                   {}};
  if (auto refusal = collider_refusal(scene, who)) return refusal;
  for (size_t p = 0; p < scene.held.size(); ++p)
    if (scene.held[p] & ~cloth::kHoldAll)
      return Refusal{who + "particle " + std::to_string(p) +
                         " has a held-axis mask with bits other than x, y and z (" +
                         std::to_string(int(scene.held[p])) + ")",
                     {"constraint"},
                     {}};
  return std::nullopt;
}

btSoftBody* build_soft_body(btSoftBodyWorldInfo& info, const cloth::Model& model,
                            const cloth::Matrix3X& start, const LinkMaterial& material) {
  const int n = model.particle_count();
  // nodes in our order; a particle held on all axes is a pin: mass 0, which Bullet never moves
  std::vector<btVector3> x(static_cast<size_t>(n));
  std::vector<btScalar> mass(static_cast<size_t>(n));
  for (int p = 0; p < n; ++p) {
    x[size_t(p)] = to_bt(model.x0.col(p));
    const bool pinned = model.free.col(p).isZero();
    mass[size_t(p)] = pinned ? 0.0 : model.mass[p];
  }
  auto* body = new btSoftBody(&info, n, x.data(), mass.data());
  // links in our order; Bullet takes the rest length from the same rest positions
  for (const cloth::SpringLink& s : model.springs.links()) {
    body->appendLink(s.a, s.b, material(*body, s), false);
    btSoftBody::Link& l = body->m_links[body->m_links.size() - 1];
    l.m_bbending = s.kind == cloth::SpringKind::bend ? 1 : 0;
  }
  // the cloth's surface (a grid's cells split along a diagonal, a mesh's faces), for collision
  // normals and Bullet's face-based queries
  for (const cloth::Triangle& tri : model.triangles) body->appendFace(tri[0], tri[1], tri[2]);
  // the start state, once the rest lengths are taken from the rest positions
  for (int p = 0; p < n; ++p) {
    btSoftBody::Node& node = body->m_nodes[p];
    node.m_x = node.m_q = to_bt(start.col(p));
  }
  body->updateBounds();
  return body;
}

cloth::Matrix3X start_positions(const cloth::Model& model, const cloth::Scene& scene) {
  cloth::Matrix3X x = model.x0;
  cloth::Matrix3X v = cloth::Matrix3X::Zero(3, x.cols());
  cloth::resolve_sphere_contacts(scene.spheres, 0.0, x, v, model.mass, model.free);
  return x;
}

double sdf_voxel_size(const cloth::Scene& scene) {
  // Bullet's default cell of 0.25 m would put the unit sphere's surface ~8 mm off
  double voxel = 0.25;
  for (const cloth::Sphere& s : scene.spheres) voxel = std::min(voxel, s.radius / 20.0);
  const cloth::Shapes& sh = scene.shapes;
  if (!sh.planes.empty()) voxel = std::min(voxel, 0.1);  // the plane's 2 m box
  for (const cloth::Box& b : sh.boxes) voxel = std::min(voxel, b.half_extents.minCoeff() / 10.0);
  for (const cloth::Capsule& c : sh.capsules) voxel = std::min(voxel, c.radius / 20.0);
  for (const cloth::Cylinder& c : sh.cylinders)
    voxel = std::min(voxel, c.radius / 20.0);  // exact on the flat top, edges rounded
  return voxel;
}

double collider_margin(const cloth::Scene& scene) {
  const cloth::Shapes& s = scene.shapes;
  if (!scene.spheres.empty()) return scene.spheres.front().margin;
  if (!s.planes.empty()) return s.planes.front().margin;
  if (!s.boxes.empty()) return s.boxes.front().margin;
  if (!s.capsules.empty()) return s.capsules.front().margin;
  if (!s.cylinders.empty()) return s.cylinders.front().margin;
  return 0.01;
}

void set_up_world(btDiscreteDynamicsWorld& world, btSoftBodyWorldInfo& info,
                  const cloth::Scene& scene) {
  world.setGravity(to_bt(scene.gravity));
  info.m_gravity = to_bt(scene.gravity);
  info.m_sparsesdf.setDefaultVoxelsz(sdf_voxel_size(scene));
  info.m_sparsesdf.Reset();
}

void step_world(btDiscreteDynamicsWorld& world, btSoftBodyWorldInfo& info, ColliderBodies& bodies,
                double t, double dt) {
  bodies.move_to(t + dt);
  world.stepSimulation(dt, 0, dt);
  info.m_sparsesdf.GarbageCollect();
}

void set_contact_config(btSoftBody& body, const cloth::Scene& scene) {
  btSoftBody::Config& cfg = body.m_cfg;
  cfg.kCHR = 1.0;
  cfg.kKHR = 1.0;  // Bullet's default 0.1 makes static spheres ten times softer
  cfg.kDF = 1.0;
  body.getCollisionShape()->setMargin(collider_margin(scene));
  body.setActivationState(DISABLE_DEACTIVATION);
}

namespace {

// the rotation that turns +y onto the unit vector u
btQuaternion y_onto(const cloth::Vector3& u) {
  const btVector3 y(0, 1, 0), to = to_bt(u);
  const btVector3 axis = y.cross(to);
  if (axis.length() < 1e-12)
    return to.y() > 0 ? btQuaternion::getIdentity() : btQuaternion(btVector3(1, 0, 0), SIMD_PI);
  return btQuaternion(axis.normalized(), std::acos(std::clamp(double(y.dot(to)), -1.0, 1.0)));
}

}  // namespace

ColliderBodies::ColliderBodies(btDiscreteDynamicsWorld& world, const cloth::Scene& scene)
    : m_world(world) {
  const btQuaternion none = btQuaternion::getIdentity();
  for (const cloth::Sphere& s : scene.spheres)
    add(std::make_unique<btSphereShape>(s.radius), s, s.center, none);
  for (const cloth::HalfSpace& p : scene.shapes.planes) {
    // Bullet has no infinite plane for soft bodies: a 200 m x 2 m x 200 m box whose top face
    // lies in the plane, centred under the cloth (the plane's point may lie anywhere on it)
    const cloth::Vector3 n = p.normal.normalized();
    const cloth::Vector3 under_cloth =
        scene.cloth.center - (scene.cloth.center - p.point).dot(n) * n;
    add(std::make_unique<btBoxShape>(btVector3(100.0, 1.0, 100.0)), p, under_cloth - n, y_onto(n));
  }
  for (const cloth::Box& b : scene.shapes.boxes)
    add(std::make_unique<btBoxShape>(to_bt(b.half_extents)), b, b.center, none);
  for (const cloth::Capsule& c : scene.shapes.capsules)
    add(std::make_unique<btCapsuleShape>(c.radius, (c.b - c.a).norm()), c, 0.5 * (c.a + c.b),
        y_onto((c.b - c.a).normalized()));
  for (const cloth::Cylinder& c : scene.shapes.cylinders)
    add(std::make_unique<btCylinderShape>(btVector3(c.radius, 0.5 * c.height, c.radius)), c,
        c.center, none);
}

void ColliderBodies::add(std::unique_ptr<btCollisionShape> shape, const cloth::Collider& c,
                         const cloth::Vector3& origin, const btQuaternion& rotation) {
  Body b;
  b.motion = c;
  b.start = btTransform(rotation, to_bt(origin));
  b.shape = std::move(shape);
  b.state = std::make_unique<btDefaultMotionState>(b.start);
  btRigidBody::btRigidBodyConstructionInfo ci(0.0, b.state.get(), b.shape.get());
  ci.m_friction = c.friction;
  ci.m_restitution = 0.0;
  b.body = std::make_unique<btRigidBody>(ci);
  // a moving collider is kinematic: Bullet reads its pose from the motion state every step
  if (c.moves())
    b.body->setCollisionFlags(b.body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  b.body->setActivationState(DISABLE_DEACTIVATION);
  m_world.addRigidBody(b.body.get());
  m_bodies.push_back(std::move(b));
}

ColliderBodies::~ColliderBodies() {
  for (Body& b : m_bodies) m_world.removeRigidBody(b.body.get());
}

btTransform ColliderBodies::pose_at(const Body& b, double t) {
  btTransform pose = b.start;
  pose.setOrigin(b.start.getOrigin() + to_bt(b.motion.displacement(t)));
  return pose;
}

void ColliderBodies::move_to(double t) {
  for (Body& b : m_bodies)
    if (b.motion.moves()) b.state->setWorldTransform(pose_at(b, t));
}

void ColliderBodies::place_at(double t) {
  const btVector3 zero(0, 0, 0);
  for (Body& b : m_bodies) {
    if (!b.motion.moves()) continue;
    // the pose of the last step is the one the next step's velocity is measured from
    const btTransform pose = pose_at(b, t);
    b.state->setWorldTransform(pose);
    b.body->setWorldTransform(pose);
    b.body->setInterpolationWorldTransform(pose);
    b.body->setLinearVelocity(zero);
    b.body->setAngularVelocity(zero);
    b.body->setInterpolationLinearVelocity(zero);
    b.body->setInterpolationAngularVelocity(zero);
  }
}

BulletCloth::BulletCloth(const cloth::Scene& scene, Dissipation book)
    : m_model(cloth::build_model(scene)), m_book(book) {
  const int n = m_model.particle_count();
  m_x = start_positions(m_model, scene);
  m_v = cloth::Matrix3X::Zero(3, n);
  std::vector<bool> in_handle(static_cast<size_t>(n), false);
  for (const cloth::Handle& h : m_model.handles)
    for (int p : h.particles) in_handle[size_t(p)] = true;
  for (int p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a)
      if (m_model.free(a, p) == 0.0 && !in_handle[size_t(p)])
        m_holds.push_back({p, a, m_model.x0(a, p)});
  m_energy = cloth::compute_energies(m_model, m_x, m_v).total();
}

void BulletCloth::step(double dt) {
  start_handles(dt);
  advance(dt);
  apply_air_drag(dt);
  project_held_axes();
  project_handles(m_t + dt);
  // copy the nodes back in our order
  const btSoftBody::tNodeArray& nodes = m_body->m_nodes;
  for (int p = 0; p < nodes.size(); ++p) {
    for (int a = 0; a < 3; ++a) {
      m_x(a, p) = nodes[p].m_x[a];
      m_v(a, p) = nodes[p].m_v[a];
    }
  }
  const double e = cloth::compute_energies(m_model, m_x, m_v).total();
  if (m_book == Dissipation::damper_power) {
    // the damping power of the new state (springs and drag), as the custom implicit engine
    // books it
    const double booked =
        dt * (cloth::damping_power(m_model.springs, m_x, m_v) + m_model.drag_power(m_v));
    m_dissipated += booked;
    // a contact step's balance is contact work and scheme error together: kept apart, so that
    // energy_error is the scheme's own on the other steps (the harness books a step in which a
    // handle moved: its holder's work, and the rest as unbooked)
    if (had_contact()) m_unbooked += e - m_energy + booked;
  } else if (!handles_moved(dt)) {
    // what the step took out, whatever took it (but for the handles' holder's work, which the
    // harness books with the rest of such a step)
    m_dissipated += m_energy - e;
  }
  m_energy = e;
  m_t += dt;
  ++m_counters.steps;
}

void BulletCloth::set_state(const cloth::Matrix3X& x, const cloth::Matrix3X& v, double t) {
  const int n = m_model.particle_count();
  if (x.rows() != 3 || x.cols() != n || v.rows() != 3 || v.cols() != n)
    throw std::invalid_argument("set_state: x and v must be 3 by " + std::to_string(n) +
                                ", got 3 by " + std::to_string(x.cols()) + " and 3 by " +
                                std::to_string(v.cols()));
  // a fresh engine's first step would take the rest lengths from the state: take them first
  take_first_step_constants();
  // the nodes as a step leaves them: previous positions and velocities equal to the current
  const btVector3 zero(0, 0, 0);
  for (int p = 0; p < n; ++p) {
    btSoftBody::Node& node = m_body->m_nodes[p];
    node.m_x = node.m_q = to_bt(x.col(p));
    node.m_v = node.m_vn = to_bt(v.col(p));
    node.m_f = zero;
    node.m_splitv = zero;
  }
  // the body's box in the broadphase, and its face normals, from the new positions
  m_body->updateBounds();
  m_body->updateNormals();
  reset_world(t);
  // our copies; the books go on from the energy of the new state
  m_x = x;
  m_v = v;
  m_t = t;
  m_energy = cloth::compute_energies(m_model, m_x, m_v).total();
}

void BulletCloth::take_first_step_constants() {
  if (!m_body->m_bUpdateRtCst) return;
  // as btSoftBody::predictMotion and btDeformableBodySolver::predictDeformableMotion do
  m_body->m_bUpdateRtCst = false;
  m_body->updateConstants();
  m_body->m_fdbvt.clear();
  if (m_body->m_cfg.collisions & m_face_tree_flags) m_body->initializeFaceTree();
}

void BulletCloth::apply_air_drag(double dt) {
  if (m_model.air_drag == 0.0) return;
  for (int p = 0; p < m_body->m_nodes.size(); ++p) {
    // m v' = m v - h c (v' - wind): the drag sub-step solved implicitly, unconditionally stable
    const double a = dt * m_model.air_drag * m_model.inv_mass[p];
    const btVector3 wind = to_bt(m_model.wind);
    btSoftBody::Node& n = m_body->m_nodes[p];
    n.m_v = (n.m_v + a * wind) / (1.0 + a);
    n.m_vn = (n.m_vn + a * wind) / (1.0 + a);
  }
}

bool BulletCloth::handles_moved(double dt) const {
  for (const cloth::Handle& h : m_model.handles)
    if (h.motion.displacement(m_t + dt) != h.motion.displacement(m_t)) return true;
  return false;
}

void BulletCloth::start_handles(double dt) {
  for (const cloth::Handle& h : m_model.handles) {
    const cloth::Vector3 v = (h.motion.displacement(m_t + dt) - h.motion.displacement(m_t)) / dt;
    for (int p : h.particles) m_body->m_nodes[p].m_v = m_body->m_nodes[p].m_vn = to_bt(v);
  }
}

void BulletCloth::project_handles(double t) {
  for (const cloth::Handle& h : m_model.handles) {
    const cloth::Vector3 d = h.motion.displacement(t);
    for (int p : h.particles) {
      btSoftBody::Node& n = m_body->m_nodes[p];
      n.m_x = n.m_q = to_bt(cloth::Vector3(m_model.x0.col(p) + d));
    }
  }
}

void BulletCloth::project_held_axes() {
  for (const Hold& h : m_holds) {
    btSoftBody::Node& n = m_body->m_nodes[h.node];
    n.m_x[h.axis] = h.value;
    n.m_q[h.axis] = h.value;
    n.m_v[h.axis] = 0.0;
    n.m_vn[h.axis] = 0.0;
  }
}

}  // namespace clothbench::reference
