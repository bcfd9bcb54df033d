#include "reference/mujoco/mujoco_cloth.hpp"

#include <mujoco/mujoco.h>

#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>

#include "cloth/forces/energies.hpp"
#include "cloth/forces/spring_forces.hpp"
#include "reference/mujoco/mujoco_mjcf.hpp"

namespace clothbench::reference {

namespace {

/// MuJoCo's fatal errors (a stack overflow, a bad model) as exceptions: its default handler
/// writes MUJOCO_LOG.TXT into the working folder and exits the process.
[[noreturn]] void throw_mujoco_error(const char* msg) {
  throw std::runtime_error(std::string("mujoco: ") + msg);
}

/// MuJoCo's warnings are read from mjData's counters after each step; its default handler
/// prints them and writes MUJOCO_LOG.TXT.
void ignore_mujoco_warning(const char*) {}

/// The MJCF text compiled by MuJoCo from a virtual file (never a file on disk). MuJoCo 2.2's
/// parser keeps the last model in a global, so loads are serialised.
mjModel* load_from_memory(const std::string& xml) {
  static std::once_flag handlers;
  std::call_once(handlers, [] {
    mju_user_error = throw_mujoco_error;
    mju_user_warning = ignore_mujoco_warning;
  });
  static std::mutex parser;
  std::lock_guard<std::mutex> lock(parser);
  // mjVFS holds 2000 file names of 1000 characters: too big for the stack
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* name = "clothbench.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0)
    throw std::runtime_error("mujoco: could not make the model's virtual file");
  const int file = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[file], xml.data(), xml.size());
  char error[1000] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("mujoco: the model did not compile: ") + error);
  return m;
}

}  // namespace

/// The Simulator on one MuJoCo model and its data.
class MujocoCloth : public cloth::Simulator {
 public:
  MujocoCloth(const MujocoOptions& options, double dt, const cloth::Scene& scene);
  ~MujocoCloth() override;
  MujocoCloth(const MujocoCloth&) = delete;
  MujocoCloth& operator=(const MujocoCloth&) = delete;

  void step(double dt) override;
  const cloth::Matrix3X& positions() const override { return m_x; }
  const cloth::Matrix3X& velocities() const override { return m_v; }
  double time() const override { return m_t; }
  double dissipated() const override { return m_dissipated; }
  double unbooked() const override { return m_unbooked; }
  int contacts() const override { return m_contacts; }
  cloth::Vector3 contact_impulse() const override { return m_impulse; }
  cloth::Counters counters() const override { return m_counters; }
  bool can_set_state() const override { return true; }
  void set_state(const cloth::Matrix3X& x, const cloth::Matrix3X& v, double t) override;

  /// The sizes of the model and data.
  MujocoMeasure measure() const;

 private:
  /// Puts the mocap bodies (handle particles, moving colliders) where they are at time t (s).
  void place_mocap(double t);
  /// Sets qfrc_applied to the air drag -c (v - w) of the current velocities, or to its wind part
  /// c w alone where the joints damp (air_drag_in_joints).
  void apply_air_drag();
  /// Copies MuJoCo's state at time t into m_x and m_v.
  void read_state(double t);
  /// True when MuJoCo reset its state in the last step because it became non-finite or too
  /// large; throws when the contact or constraint budget overflowed.
  bool check_warnings();

  cloth::Model m_model;
  MujocoOptions m_options;
  MujocoSize m_size;
  MjcfLayout m_layout;
  mjModel* m_m = nullptr;
  mjData* m_d = nullptr;
  cloth::Matrix3X m_x, m_v;
  double m_t = 0;
  double m_energy = 0;  // J, our total energy of the current state
  double m_dissipated = 0;
  double m_unbooked = 0;
  int m_contacts = 0;
  bool m_failed = false;  // MuJoCo reset a non-finite state: the run has blown up
  cloth::Vector3 m_impulse = cloth::Vector3::Zero();
  cloth::Counters m_counters;
};

MujocoCloth::MujocoCloth(const MujocoOptions& options, double dt, const cloth::Scene& scene)
    : m_model(cloth::build_model(scene)), m_options(options) {
  m_size = mujoco_size(m_model, options);
  m_layout = mjcf_layout(m_model);
  m_m = load_from_memory(mujoco_mjcf(m_model, options, dt, m_size, m_layout));
  m_d = mj_makeData(m_m);
  if (!m_d) {
    mj_deleteModel(m_m);
    throw std::runtime_error("mujoco: could not allocate the model's data");
  }
  place_mocap(0.0);
  read_state(0.0);
  m_energy = cloth::compute_energies(m_model, m_x, m_v).total();
}

MujocoCloth::~MujocoCloth() {
  mj_deleteData(m_d);
  mj_deleteModel(m_m);
}

void MujocoCloth::place_mocap(double t) {
  for (size_t c = 0; c < m_layout.moving.size(); ++c) {
    const cloth::Vector3 at = m_layout.moving_start[c] + m_layout.moving[c]->displacement(t);
    for (int a = 0; a < 3; ++a) m_d->mocap_pos[3 * c + size_t(a)] = at[a];
  }
  for (int p = 0; p < m_model.particle_count(); ++p) {
    const int k = m_layout.particle_mocap[size_t(p)];
    if (k < 0) continue;
    const cloth::Handle& h = m_model.handles[size_t(m_layout.handle_of[size_t(p)])];
    const cloth::Vector3 at = m_model.x0.col(p) + h.motion.displacement(t);
    for (int a = 0; a < 3; ++a) m_d->mocap_pos[3 * k + a] = at[a];
  }
}

void MujocoCloth::apply_air_drag() {
  const double c = m_model.air_drag;
  // with the -c v part in the joints' damping only the wind's constant c w is applied here
  const bool drag_in_joints = air_drag_in_joints(m_options);
  for (int p = 0; p < m_model.particle_count(); ++p)
    for (int a = 0; a < 3; ++a) {
      const int i = m_layout.dof[size_t(p)][size_t(a)];
      if (i < 0) continue;
      m_d->qfrc_applied[i] =
          drag_in_joints ? c * m_model.wind[a] : -c * (m_d->qvel[i] - m_model.wind[a]);
    }
}

void MujocoCloth::read_state(double t) {
  const int n = m_model.particle_count();
  m_x = m_model.x0;
  m_v = cloth::Matrix3X::Zero(3, n);
  for (int p = 0; p < n; ++p) {
    const int h = m_layout.handle_of[size_t(p)];
    if (h >= 0) {
      const cloth::Motion& motion = m_model.handles[size_t(h)].motion;
      m_x.col(p) += motion.displacement(t);
      m_v.col(p) = motion.velocity_at(t);
      continue;
    }
    for (int a = 0; a < 3; ++a) {
      const int i = m_layout.dof[size_t(p)][size_t(a)];
      if (i < 0) continue;
      m_x(a, p) += m_d->qpos[i];
      m_v(a, p) = m_d->qvel[i];
    }
  }
}

bool MujocoCloth::check_warnings() {
  if (m_d->warning[mjWARN_CONTACTFULL].number > 0 || m_d->warning[mjWARN_CNSTRFULL].number > 0)
    throw std::runtime_error("mujoco: more contacts than the model has room for (" +
                             std::to_string(m_size.contacts) +
                             ", one per particle): a particle touched two colliders at once");
  const int bad = m_d->warning[mjWARN_BADQPOS].number + m_d->warning[mjWARN_BADQVEL].number +
                  m_d->warning[mjWARN_BADQACC].number;
  return bad > 0;
}

void MujocoCloth::step(double dt) {
  if (m_failed) {
    // MuJoCo reset a blown-up state: the run stays blown up, as the other engines' would
    m_t += dt;
    ++m_counters.steps;
    return;
  }
  m_m->opt.timestep = dt;
  apply_air_drag();
  mj_step(m_m, m_d);
  m_contacts = m_d->ncon;
  // every constraint is a contact: its generalised force on a slide joint is the force along
  // that axis
  for (int p = 0; p < m_model.particle_count(); ++p)
    for (int a = 0; a < 3; ++a) {
      const int i = m_layout.dof[size_t(p)][size_t(a)];
      if (i >= 0) m_impulse[a] += dt * m_d->qfrc_constraint[i];
    }
  place_mocap(m_t + dt);
  read_state(m_t + dt);
  if (check_warnings()) {
    m_failed = true;
    m_x.setConstant(NAN);
    m_v.setConstant(NAN);
  }
  // the damping power of the new state (springs and drag), booked as the Bullet adapters do
  const double e = cloth::compute_energies(m_model, m_x, m_v).total();
  const double booked =
      dt * (cloth::damping_power(m_model.springs, m_x, m_v) + m_model.drag_power(m_v));
  m_dissipated += booked;
  // a contact step's balance (the harness books a step in which a handle moved: its holder's
  // work, and the rest as unbooked)
  if (m_contacts > 0) m_unbooked += e - m_energy + booked;
  m_energy = e;
  m_t += dt;
  ++m_counters.steps;
  m_counters.force_evals += m_options.integrator == MujocoIntegrator::rk4 ? 4 : 1;
}

void MujocoCloth::set_state(const cloth::Matrix3X& x, const cloth::Matrix3X& v, double t) {
  const int n = m_model.particle_count();
  if (x.rows() != 3 || x.cols() != n || v.rows() != 3 || v.cols() != n)
    throw std::invalid_argument("set_state: x and v must be 3 by " + std::to_string(n) +
                                ", got 3 by " + std::to_string(x.cols()) + " and 3 by " +
                                std::to_string(v.cols()));
  // the free axes from the state; held axes and handles cannot be put elsewhere
  for (int p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a) {
      const int i = m_layout.dof[size_t(p)][size_t(a)];
      if (i < 0) continue;
      m_d->qpos[i] = x(a, p) - m_model.x0(a, p);
      m_d->qvel[i] = v(a, p);
    }
  // no warm start from another state: the solver starts as at t = 0
  mju_zero(m_d->qacc_warmstart, m_m->nv);
  m_d->time = t;
  m_t = t;
  m_failed = false;
  for (mjWarningStat& w : m_d->warning) w.number = 0;
  place_mocap(t);
  read_state(t);
  m_energy = cloth::compute_energies(m_model, m_x, m_v).total();
}

MujocoMeasure MujocoCloth::measure() const {
  MujocoMeasure r;
  r.size = m_size;
  r.model_bytes = mj_sizeModel(m_m);
  r.buffer_bytes = m_d->nbuffer;
  r.stack_bytes = double(m_d->nstack) * sizeof(mjtNum);
  r.stack_used = double(m_d->maxuse_stack) * sizeof(mjtNum);
  return r;
}

std::unique_ptr<cloth::Simulator> make_mujoco_cloth(const MujocoOptions& options, double dt,
                                                    const cloth::Scene& scene) {
  if (const auto refusal = mujoco_refusal(options, scene))
    throw std::invalid_argument(refusal->why);
  return std::make_unique<MujocoCloth>(options, dt, scene);
}

MujocoMeasure mujoco_measure(const cloth::Simulator& engine) {
  return dynamic_cast<const MujocoCloth&>(engine).measure();
}

}  // namespace clothbench::reference
