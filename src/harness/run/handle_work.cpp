#include "harness/run/handle_work.hpp"

#include "cloth/forces/spring_forces.hpp"

namespace clothbench {

namespace {

/// The springs of s with an end among the marked particles, as a general list, with s's
/// damping and bending form: every force they give a marked particle is all s gives it.
cloth::SpringSet springs_touching(const cloth::SpringSet& s, const std::vector<char>& marked) {
  cloth::SpringSet out;
  out.damping = s.damping;
  out.bending = s.bending;
  for (const cloth::SpringLink& l : s.links())
    if (marked[size_t(l.a)] || marked[size_t(l.b)]) out.list.push_back(l);
  return out;
}

}  // namespace

HandleWorkMeter::HandleWorkMeter(const cloth::Model& model, double t, const cloth::Matrix3X& x,
                                 const cloth::Matrix3X& v)
    : m_model(model), m_t(t) {
  if (model.handles.empty()) return;
  std::vector<char> marked(size_t(model.particle_count()), 0);
  for (size_t h = 0; h < model.handles.size(); ++h)
    for (int p : model.handles[h].particles) {
      m_particles.push_back(p);
      m_handle_of.push_back(int(h));
      marked[size_t(p)] = 1;
    }
  m_springs = springs_touching(model.springs, marked);
  m_force.resize(3, model.particle_count());
  m_buf.resize(3, model.particle_count());
  m_load.resize(3, Eigen::Index(m_particles.size()));
  m_next.resize(3, Eigen::Index(m_particles.size()));
  m_x = x;
  m_v = v;
  m_kinetic = load(x, v, m_load);
}

double HandleWorkMeter::load(const cloth::Matrix3X& x, const cloth::Matrix3X& v,
                             cloth::Matrix3X& g) {
  m_force.setZero();
  cloth::add_spring_forces(m_springs, x, v, m_force, m_buf);
  double kinetic = 0.0;
  const double drag = m_model.air_drag;
  for (size_t k = 0; k < m_particles.size(); ++k) {
    const int p = m_particles[k];
    const double m = m_model.mass[p];
    g.col(Eigen::Index(k)) = m_force.col(p) + m * m_model.gravity;
    if (drag != 0.0) g.col(Eigen::Index(k)) -= drag * (v.col(p) - m_model.wind);
    kinetic += 0.5 * m * v.col(p).squaredNorm();
  }
  return kinetic;
}

void HandleWorkMeter::start_load(double t) {
  for (size_t k = 0; k < m_particles.size(); ++k) {
    const cloth::Motion& motion = m_model.handles[size_t(m_handle_of[k])].motion;
    m_v.col(m_particles[k]) = (motion.displacement(t) - motion.displacement(m_t)) / (t - m_t);
  }
  load(m_x, m_v, m_load);
}

double HandleWorkMeter::observe(double t, const cloth::Matrix3X& x, const cloth::Matrix3X& v) {
  m_moved = false;
  if (!active() || !(t > m_t)) return 0.0;
  start_load(t);
  const double kinetic = load(x, v, m_next);
  // the kinetic energy the holder gave, and its force against the load along the path
  double w = kinetic - m_kinetic;
  for (size_t k = 0; k < m_particles.size(); ++k) {
    const cloth::Motion& motion = m_model.handles[size_t(m_handle_of[k])].motion;
    const cloth::Vector3 d = motion.displacement(t) - motion.displacement(m_t);
    if (d == cloth::Vector3::Zero()) continue;
    m_moved = true;
    w -= 0.5 * (m_load.col(Eigen::Index(k)) + m_next.col(Eigen::Index(k))).dot(d);
  }
  m_x = x;
  m_v = v;
  m_kinetic = kinetic;
  m_t = t;
  m_work += w;
  return w;
}

}  // namespace clothbench
