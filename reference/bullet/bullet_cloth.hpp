#pragma once
/// @file bullet_cloth.hpp
/// What both Bullet adapters share (internal to reference/, the only code that includes
/// Bullet): the checks every Bullet engine makes on a scene, the soft body built node by node
/// and link by link from our model, the spheres as rigid bodies, held axes restored by
/// projection, and the Simulator bookkeeping done the same way as the custom engine's.

#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <btBulletDynamicsCommon.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cloth/model/model.hpp"
#include "cloth/model/scene.hpp"
#include "cloth/model/simulator.hpp"
#include "reference/bullet/bullet_options.hpp"
#include "reference/refusal.hpp"

namespace clothbench::reference {

/// Our vector as Bullet's.
inline btVector3 to_bt(const cloth::Vector3& v) {
  return btVector3(v.x(), v.y(), v.z());
}

/// What no Bullet soft body can model the way the scene means it, naming the engine kind and
/// the feature: restitution (Bullet's soft contacts are inelastic), spheres with different
/// contact margins (one margin per soft body), negative air drag and held-axis masks with bits
/// other than x, y and z; nullopt when there is none of that.
std::optional<Refusal> bullet_scene_refusal(const cloth::Scene& scene, const std::string& kind);

/// The first collider whose friction exceeds 1 (the classic soft body's kDF * friction is a
/// fraction of the tangential velocity), refused in the words of who ("bullet-softbody: ").
std::optional<Refusal> friction_above_one(const cloth::Scene& scene, const std::string& who);

/// Picks the material of one link (nullptr: the body's default material).
using LinkMaterial =
    std::function<btSoftBody::Material*(btSoftBody& body, const cloth::SpringLink&)>;

/// A soft body with our particles as nodes (same order; pinned particles, all axes held, get
/// mass 0), our springs as links (same order, rest lengths from the same rest positions, bend
/// links flagged m_bbending) and two triangles per grid cell as faces, its nodes then placed
/// at start. The caller adds it to a world and owns it.
/// @param info      the world's soft-body info (gravity, sparse SDF)
/// @param start     3 by #P node positions at t = 0 (m): start_positions()
/// @param material  material of each link
btSoftBody* build_soft_body(btSoftBodyWorldInfo& info, const cloth::Model& model,
                            const cloth::Matrix3X& start, const LinkMaterial& material);

/// 3 by #P positions (m) a Bullet cloth starts from: the rest positions with every particle
/// that starts inside a sphere's contact shell (radius + margin) moved onto it along its free
/// axes, by the custom engine's own contact projection (cloth::resolve_sphere_contacts, which
/// the custom engine applies after its first step). Bullet would turn the overlap into
/// velocity: the classic soft body's contact (kKHR = 1) removes it in one step, so the seed
/// scene's pole node left at 10 m/s (50 J), and the deformable world's explicit scheme turns
/// its split impulses into a velocity that depends on round-off (see bullet_deformable.hpp).
cloth::Matrix3X start_positions(const cloth::Model& model, const cloth::Scene& scene);

/// Sparse-SDF voxel size (m) fine enough that the interpolated sphere surface is within
/// radius / 3200 of the true one (trilinear error ~ voxel^2 / (8 radius)), and a twentieth of
/// every other shape's smallest dimension.
double sdf_voxel_size(const cloth::Scene& scene);

/// The contact margin of the scene's colliders (they all have one, bullet_scene_refusal checks):
/// the first collider's, 0.01 m when there is none.
double collider_margin(const cloth::Scene& scene);

/// The scene's colliders as rigid bodies: static, or kinematic when they move. A plane is a
/// box 200 m wide and 2 m thick whose face is the plane (Bullet's sparse SDF, through which
/// soft bodies meet rigid ones, measures convex shapes only); a capsule is btCapsuleShape
/// turned from y onto a-b, a cylinder btCylinderShape (axis along y).
class ColliderBodies {
 public:
  /// Adds the colliders to world with the scene's friction (Bullet's soft-rigid friction is
  /// the soft body's kDF, 1 here, times the rigid body's); world must outlive this object.
  ColliderBodies(btDiscreteDynamicsWorld& world, const cloth::Scene& scene);
  /// Removes the bodies from the world and frees them.
  ~ColliderBodies();
  ColliderBodies(const ColliderBodies&) = delete;
  ColliderBodies& operator=(const ColliderBodies&) = delete;

  /// Puts the kinematic bodies where they are at time t (s); Bullet takes their velocity
  /// from the change of pose over the next step.
  void move_to(double t);
  /// Puts the kinematic bodies at their pose at time t (s) as the pose of the last step too
  /// (motion state, world transform and the interpolation transform Bullet takes the next
  /// step's velocity from, btRigidBody::saveKinematicState, btRigidBody.cpp:105-121), with zero
  /// velocity until that step recomputes it: the next step then moves them as if a run had
  /// arrived at t.
  void place_at(double t);

 private:
  struct Body;
  /// The pose of b at time t (s).
  static btTransform pose_at(const Body& b, double t);
  /// Adds one body of shape with the pose (origin at t = 0, rotation) and motion of c.
  void add(std::unique_ptr<btCollisionShape> shape, const cloth::Collider& c,
           const cloth::Vector3& origin, const btQuaternion& rotation);

  struct Body {
    cloth::Motion motion;
    btTransform start;
    std::unique_ptr<btCollisionShape> shape;
    std::unique_ptr<btDefaultMotionState> state;
    std::unique_ptr<btRigidBody> body;
  };
  btDiscreteDynamicsWorld& m_world;
  std::vector<Body> m_bodies;
};

/// The collision machinery every soft-body world is built on. Declare it before the world
/// so that it outlives it.
struct CollisionParts {
  std::unique_ptr<btSoftBodyRigidBodyCollisionConfiguration> config =
      std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
  std::unique_ptr<btCollisionDispatcher> dispatcher =
      std::make_unique<btCollisionDispatcher>(config.get());
  std::unique_ptr<btDbvtBroadphase> broadphase = std::make_unique<btDbvtBroadphase>();
};

/// Sets the gravity of world and of its soft bodies (info, where classic soft bodies read
/// it), and a sparse-SDF voxel fine enough for the spheres.
void set_up_world(btDiscreteDynamicsWorld& world, btSoftBodyWorldInfo& info,
                  const cloth::Scene& scene);

/// One fixed step of world: the kinematic colliders moved to their pose at t + dt,
/// stepSimulation(dt, 0, dt), then sparse-SDF cells unused for a while dropped (as Bullet's
/// own demos do every frame).
void step_world(btDiscreteDynamicsWorld& world, btSoftBodyWorldInfo& info, ColliderBodies& bodies,
                double t, double dt);

/// The contact settings both engines share: node contacts as hard against static and
/// kinematic colliders as against dynamic ones (kCHR = kKHR = 1), friction = the collider's
/// (kDF = 1), the scene's margin, never put to sleep.
void set_contact_config(btSoftBody& body, const cloth::Scene& scene);

/// How a Bullet engine books dissipated().
enum class Dissipation {
  /// h times the spring-axis damping power plus the air-drag power of the new state, as the
  /// custom implicit engine books it; contact losses are not in it (Bullet does not report
  /// them), so they show up in energy_error
  damper_power,
  /// the energy the step removed, E(before) - E(after) with our energies of the state: for an
  /// engine without a damper (the classic soft body, whose projection dissipates), so this
  /// books projection, contact and drag losses alike and its energy_error is 0 by construction
  energy_balance
};

/// The Simulator side of a Bullet engine: our model, the state copied from the nodes after
/// every step, dissipation and counters kept like the custom engine's. What Bullet's soft
/// bodies lack is added after every Bullet step (operator splitting, first order in dt like
/// the engines it is compared with): the scene's viscous air drag, then the held axes.
class BulletCloth : public cloth::Simulator {
 public:
  void step(double dt) override;
  /// At t = 0: start_positions(), not the rest positions, when a particle starts in contact.
  const cloth::Matrix3X& positions() const override { return m_x; }
  const cloth::Matrix3X& velocities() const override { return m_v; }
  double time() const override { return m_t; }
  /// Energy taken out since the start (J), booked as the Dissipation given to the constructor.
  double dissipated() const override { return m_dissipated; }
  /// The energy balance (change of our total energy plus the dissipation booked) of every
  /// step in which Bullet reported a contact (J): Bullet's contact response and its scheme's
  /// error in that step cannot be told apart from its state. 0 for energy_balance booking,
  /// whose balance is 0 by construction.
  double unbooked() const override { return m_unbooked; }
  cloth::Counters counters() const override { return m_counters; }
  /// True: both Bullet engines can be put into a state.
  bool can_set_state() const override { return true; }
  /// Writes the state into every node as a step of this adapter leaves it: m_x = m_q = x,
  /// m_v = m_vn = v (a step ends with m_q = m_x and m_vn = m_v, btDeformableBodySolver.cpp:
  /// 535-537, and the classic step overwrites m_q before it reads it, btSoftBody.cpp:2128),
  /// m_f = m_splitv = 0 (zeroed at the end of a classic step, btSoftBody.cpp:2270, and at the
  /// start of a deformable one, btDeformableBodySolver.cpp:470), the body's bounds and
  /// broadphase box from the new positions, and the moving colliders placed at t
  /// (reset_world). An engine that has not stepped yet first takes the constants its first
  /// step would take from the nodes (take_first_step_constants): left to that step, they would
  /// be taken from x, and every link's rest length would become its length in x (measured: a
  /// fresh engine set to a run's state then stepped 3 steps to states 2e-4 to 1e-3 off the
  /// run's). Our copies of the state, the time and the energy the books start from
  /// follow; the books themselves are kept. Held axes and handle nodes take x and v as given
  /// (the next step projects them as usual). What Bullet keeps between steps that this does not
  /// set, and what it means for the step map, is written at make_bullet_softbody and
  /// make_bullet_deformable. Throws std::invalid_argument when x or v is not 3 by #P.
  /// @param x  3 by #P positions (m)
  /// @param v  3 by #P velocities (m/s)
  /// @param t  simulated time (s)
  void set_state(const cloth::Matrix3X& x, const cloth::Matrix3X& v, double t) override;

 protected:
  BulletCloth(const cloth::Scene& scene, Dissipation book);

  /// Advances the Bullet world by one step of dt seconds.
  virtual void advance(double dt) = 0;
  /// True when Bullet's last step had a contact between the cloth and a rigid body.
  virtual bool had_contact() const = 0;
  /// Puts the engine's world (its moving colliders) at time t (s), as a run arriving there
  /// leaves it (set_state).
  virtual void reset_world(double t) = 0;
  /// The soft body holding the cloth (set by the derived constructor).
  btSoftBody* m_body = nullptr;
  /// The collision flags for which Bullet's first step builds the body's face tree (the
  /// classic step: VF_SS, btSoftBody.cpp:2109; the deformable one: SDF_RD,
  /// btDeformableBodySolver.cpp:433), set by the derived constructor.
  int m_face_tree_flags = 0;
  cloth::Model m_model;

 private:
  /// Applies the air drag -c v of the scene to the node velocities over a step of dt (Bullet
  /// has no linear drag on nodes; its m_cfg.drag is lost by the deformable implicit scheme).
  void apply_air_drag(double dt);
  /// Restores held coordinates to their initial values and zeroes held velocity components
  /// on the nodes (m_x, m_q, m_v and m_vn, so the next step starts from the projected state).
  void project_held_axes();
  /// Does now what Bullet's first step would do on its own, when no step has been
  /// taken: the runtime constants from the nodes where they are (the start positions), which
  /// resets every link's rest length to its current length (btSoftBody::updateConstants,
  /// btSoftBody.cpp:3154-3159), and the face tree. A run's links therefore have the rest
  /// lengths of start_positions(), not of the model's rest positions, where a particle starts
  /// inside a contact shell (as before set_state existed; not changed here).
  void take_first_step_constants();
  /// True when a handle's path moves over the step of dt from m_t.
  bool handles_moved(double dt) const;
  /// Gives the handle nodes the velocity that takes them along their path over the next step.
  void start_handles(double dt);
  /// Puts the handle nodes exactly on their path at time t (s).
  void project_handles(double t);

  struct Hold {
    int node = 0;
    int axis = 0;
    double value = 0;  // m
  };
  std::vector<Hold> m_holds;  // constraint axes; handle particles are moved apart
  cloth::Matrix3X m_x, m_v;
  double m_t = 0;
  Dissipation m_book;
  double m_energy = 0;  // J, our total energy of the current state
  double m_dissipated = 0;
  double m_unbooked = 0;  // J
  cloth::Counters m_counters;
};

}  // namespace clothbench::reference
