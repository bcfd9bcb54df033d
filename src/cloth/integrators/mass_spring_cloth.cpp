#include "cloth/integrators/mass_spring_cloth.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "cloth/contact/colliders.hpp"
#include "cloth/contact/sphere_collision.hpp"
#include "cloth/forces/spring_forces.hpp"
#include "cloth/integrators/xpbd.hpp"

namespace cloth {

MassSpringCloth::MassSpringCloth(const Scene& scene, const SolverOptions& options)
    : MassSpringCloth(build_model(scene), options) {}

MassSpringCloth::MassSpringCloth(Model model, const SolverOptions& options)
    : m_model(std::move(model)), m_options(options) {
  const Eigen::Index n = m_model.particle_count();
  m_x = m_model.x0;
  m_v = Matrix3X::Zero(3, n);
  for (Matrix3X* m :
       {&m_force, &m_buf, &m_x1, &m_v1, &m_k1, &m_k2, &m_k3, &m_k4, &m_rhs, &m_dv, &m_diag, &m_tmp})
    m->setZero(3, n);
  if (options.integrator == Integrator::implicit_euler ||
      options.integrator == Integrator::imex_euler)
    m_cg.resize(n);
  if (options.integrator == Integrator::implicit_euler && minimizes_potential(options.newton))
    m_newton = std::make_unique<ImplicitEulerNewton>(m_model, options);
  // the contact pass after the step: every free axis, but with a barrier in the solve only
  // the particles it does not cover (zeroed columns: counted, never moved)
  m_pass_free = m_model.free;
  if (m_newton && options.contacts == ContactMode::barrier)
    for (Eigen::Index p = 0; p < n; ++p)
      if (m_newton->barrier_covered()[static_cast<size_t>(p)]) m_pass_free.col(p).setZero();
  // xpbd and projective work on springs alone (the loader refuses such a scene first)
  if ((options.integrator == Integrator::xpbd || options.integrator == Integrator::projective) &&
      !m_model.springs.bending.empty())
    throw std::invalid_argument(std::string(integrator_name(options.integrator)) +
                                " cannot model bend_model = \"hinge\"");
  if (options.integrator == Integrator::projective)
    m_projective = std::make_unique<ProjectiveSolver>(m_model);
  if (m_model.self_collision) {
    SelfContactParams p;
    p.thickness = m_model.thickness;
    p.friction = m_model.self_friction;
    m_self = std::make_unique<SelfContact>(static_cast<int>(n), m_model.triangles, p);
    m_self_inv_mass.setZero(n);
  }
}

void MassSpringCloth::set_state(const Matrix3X& x, const Matrix3X& v) {
  // held axes keep the initial position and zero velocity
  const auto held = (1.0 - m_model.free.array());
  m_x = (x.array() * m_model.free.array() + m_model.x0.array() * held).matrix();
  m_v = v.cwiseProduct(m_model.free);
}

namespace {

/// True when x lies within kRestingSlack of the contact shell of any collider at time t (s),
/// or inside it.
bool on_a_shell(const Model& m, double t, const Vector3& x) {
  auto any_of = [&](const auto& colliders) {
    for (const auto& c : colliders)
      if (surface_point(c, t, x).distance <= c.margin + kRestingSlack) return true;
    return false;
  };
  return any_of(m.spheres) || any_of(m.shapes.planes) || any_of(m.shapes.boxes) ||
         any_of(m.shapes.capsules) || any_of(m.shapes.cylinders);
}

}  // namespace

void MassSpringCloth::set_state(const Matrix3X& x, const Matrix3X& v, double t) {
  const Eigen::Index n = m_model.particle_count();
  if (x.rows() != 3 || x.cols() != n || v.rows() != 3 || v.cols() != n)
    throw std::invalid_argument("set_state: positions and velocities must be 3 by " +
                                std::to_string(n));
  // held axes take x as given; their velocity is zero as every step leaves it, but a handle's
  // particles keep theirs (only the harness's books of the handles read it: the next step sets
  // the path's)
  m_x = x;
  m_v = v.cwiseProduct(m_model.free);
  for (const Handle& hd : m_model.handles)
    for (int p : hd.particles) m_v.col(p) = v.col(p);
  m_t = t;
  // the caches between steps: resting particles re-derived from the shells, the rest cleared
  if (m_self) {
    m_self->forget_candidates();
    m_resting.assign(static_cast<size_t>(n), 0);
    for (Eigen::Index p = 0; p < n; ++p)
      m_resting[static_cast<size_t>(p)] = on_a_shell(m_model, t, m_x.col(p)) ? 1 : 0;
  }
  if (m_newton) m_newton->forget_history();
}

double MassSpringCloth::accelerations(const Matrix3X& x, const Matrix3X& v, Matrix3X& a) {
  ++m_counters.force_evals;
  m_force.setZero();
  double power = add_spring_forces(m_model.springs, x, v, m_force, m_buf);
  m_model.add_drag(v, m_force);
  power += m_model.drag_power(v);
  // a = f / m + g on free axes only
  for (int r = 0; r < 3; ++r) {
    a.row(r) = (m_force.row(r).array() * m_model.inv_mass.transpose().array() + m_model.gravity[r])
                   .matrix();
  }
  // select, not multiply: a held axis stays exactly zero even when a blow-up makes a infinite
  if (m_model.any_held) a = (m_model.free.array() > 0.0).select(a, 0.0);
  return power;
}

double MassSpringCloth::step_rk4(double h) {
  // stage velocities are v, v + h/2 k1, v + h/2 k2, v + h k3 and k_i are the stage
  // accelerations; m_tmp gathers the weighted sum of the stage velocities
  const double p1 = accelerations(m_x, m_v, m_k1);
  m_x1 = m_x + (0.5 * h) * m_v;
  m_v1 = m_v + (0.5 * h) * m_k1;
  m_tmp = m_v + 2.0 * m_v1;
  const double p2 = accelerations(m_x1, m_v1, m_k2);
  m_x1 = m_x + (0.5 * h) * m_v1;
  m_v1 = m_v + (0.5 * h) * m_k2;
  m_tmp += 2.0 * m_v1;
  const double p3 = accelerations(m_x1, m_v1, m_k3);
  m_x1 = m_x + h * m_v1;
  m_v1 = m_v + h * m_k3;
  m_tmp += m_v1;
  const double p4 = accelerations(m_x1, m_v1, m_k4);
  m_x += (h / 6.0) * m_tmp;
  m_v += (h / 6.0) * (m_k1 + 2.0 * m_k2 + 2.0 * m_k3 + m_k4);
  return h / 6.0 * (p1 + 2.0 * p2 + 2.0 * p3 + p4);
}

void MassSpringCloth::step(double h) {
  // handles: their particles carry the path's velocity over the step (held axes keep it)
  if (!m_model.handles.empty()) start_handles(h);
  // friction shortens the step's travel; self-contact checks the step's path
  if (!m_model.shapes.empty() || m_self) m_x_start = m_x;
  integrate(h);
  m_t += h;
  ++m_counters.steps;
  if (!m_model.handles.empty()) finish_handles();
  // a scene without colliders or self-contact skips the contact pass altogether
  if (!m_model.spheres.empty() || !m_model.shapes.empty() || m_self) resolve_contacts(h);
}

void MassSpringCloth::integrate(double h) {
  double dissipated = 0.0;
  switch (m_options.integrator) {
    case Integrator::explicit_euler: {
      dissipated = h * accelerations(m_x, m_v, m_k1);
      m_x += h * m_v;
      m_v += h * m_k1;
      break;
    }
    case Integrator::symplectic_euler: {
      dissipated = h * accelerations(m_x, m_v, m_k1);
      m_v += h * m_k1;
      m_x += h * m_v;
      break;
    }
    case Integrator::picard_implicit: {
      // explicit predictor, then one evaluation at the predicted state
      accelerations(m_x, m_v, m_k1);
      m_x1 = m_x + h * m_v;
      m_v1 = m_v + h * m_k1;
      dissipated = h * accelerations(m_x1, m_v1, m_k2);
      m_x += h * m_v1;
      m_v += h * m_k2;
      break;
    }
    case Integrator::midpoint: {
      accelerations(m_x, m_v, m_k1);
      m_x1 = m_x + (0.5 * h) * m_v;
      m_v1 = m_v + (0.5 * h) * m_k1;
      dissipated = h * accelerations(m_x1, m_v1, m_k2);
      m_x += h * m_v1;
      m_v += h * m_k2;
      break;
    }
    case Integrator::rk4:
      dissipated = step_rk4(h);
      break;
    case Integrator::implicit_euler: {
      step_implicit_euler(h);
      dissipated = h * (damping_power(m_model.springs, m_x, m_v) + m_model.drag_power(m_v));
      break;
    }
    case Integrator::imex_euler: {
      step_imex_euler(h);
      // booked as the Bullet adapters book it: the damping power of the new state
      dissipated = h * (damping_power(m_model.springs, m_x, m_v) + m_model.drag_power(m_v));
      break;
    }
    case Integrator::xpbd:
      dissipated = xpbd_step(m_model, m_options, h, m_x, m_v, m_x1, m_lambda, m_counters);
      break;
    case Integrator::projective:
      dissipated = m_projective->step(m_model, m_options, h, m_x, m_v, m_counters);
      break;
  }
  m_dissipated += dissipated;
}

void MassSpringCloth::start_handles(double h) {
  // the holder sets the path's velocity at once (the harness books its work)
  for (const Handle& hd : m_model.handles) {
    const Vector3 v = (hd.motion.displacement(m_t + h) - hd.motion.displacement(m_t)) / h;
    for (int p : hd.particles) m_v.col(p) = v;
  }
}

void MassSpringCloth::finish_handles() {
  // exactly on the path, whatever the round-off of x += h v
  for (const Handle& hd : m_model.handles) {
    const Vector3 d = hd.motion.displacement(m_t);
    for (int p : hd.particles) m_x.col(p) = m_model.x0.col(p) + d;
  }
}

void MassSpringCloth::resolve_contacts(double h) {
  // the state the integrator produced (the stage scratch is free between steps)
  m_x1 = m_x;
  m_v1 = m_v;
  ContactTally tally;
  // the solve's contacts the pass does not count are counted after it; self-contact holds
  // the particles a collider touched
  if (m_newton || m_self) {
    m_touched.assign(static_cast<size_t>(m_x.cols()), 0);
    tally.touched = &m_touched;
  }
  if (!m_model.spheres.empty()) {
    resolve_sphere_contacts(m_model.spheres, m_t, m_x, m_v, m_model.mass, m_pass_free, &tally);
    m_counters.contact_tests +=
        static_cast<std::int64_t>(m_model.spheres.size()) * m_model.particle_count();
  }
  if (!m_model.shapes.empty())
    m_counters.contact_tests += resolve_shape_contacts(m_model.shapes, m_t, h, m_x_start, m_x, m_v,
                                                       m_pass_free, m_model.mass, tally);
  m_contacts = tally.contacts + held_in_solve_only();
  m_contact_impulse += tally.impulse;
  if (m_self) resolve_self_contact(h);
  // kinetic and gravity parts particle by particle (no temporaries), so the difference
  // carries no round-off of the cloth's whole energy
  double work = 0.0;
  bool moved = false;
  for (Eigen::Index p = 0; p < m_x.cols(); ++p) {
    work += 0.5 * m_model.mass[p] * (m_v.col(p).squaredNorm() - m_v1.col(p).squaredNorm());
    const Vector3 dx = m_x.col(p) - m_x1.col(p);
    if (dx == Vector3::Zero()) continue;
    moved = true;
    work -= m_model.mass[p] * m_model.gravity.dot(dx);
  }
  // the springs only when a particle moved: a cloth at rest beside the sphere pays nothing
  if (moved) work += elastic_energy(m_model.springs, m_x) - elastic_energy(m_model.springs, m_x1);
  // the moving colliders' share of it is theirs; contact_work keeps the rest
  m_collider_work += tally.collider_work;
  m_contact_work += work - tally.collider_work;
}

void MassSpringCloth::resolve_self_contact(double h) {
  // held (any axis), handled and resting particles (on a collider at this step's end and at
  // the last one's) are infinitely heavy: a layer cannot push them into the collider. A
  // particle that reached a collider in this step is not: the collider pass may have put it
  // back level with a layer it fell through, which the pass must then move it out of
  m_resting.resize(m_touched.size(), 0);
  for (Eigen::Index p = 0; p < m_x.cols(); ++p) {
    const auto k = static_cast<size_t>(p);
    const bool heavy = m_model.free.col(p).minCoeff() == 0.0 || (m_touched[k] && m_resting[k]);
    m_self_inv_mass[p] = heavy ? 0.0 : m_model.inv_mass[p];
    m_resting[k] = m_touched[k];
  }
  // the line-search solve's pushing contacts too
  if (m_newton) {
    const std::vector<ContactConstraint>& held = m_newton->contacts();
    for (size_t k = 0; k < held.size(); ++k)
      if (m_newton->impulses()[k] > 0.0) m_self_inv_mass[held[k].particle] = 0.0;
  }
  m_self_stats = m_self->resolve(h, m_x_start, m_x, m_v, m_self_inv_mass);
  m_counters.self_contact_tests += m_self_stats.tests;
}

int MassSpringCloth::held_in_solve_only() const {
  if (!m_newton) return 0;
  // in contact by the solve's constraint, pushing, and not counted by the contact pass
  int count = 0;
  const std::vector<ContactConstraint>& held = m_newton->contacts();
  for (size_t k = 0; k < held.size(); ++k) {
    const int p = held[k].particle;
    if (m_newton->impulses()[k] > 0.0 && !m_touched[static_cast<size_t>(p)]) ++count;
  }
  return count;
}

void MassSpringCloth::step_implicit_euler(double h) {
  // Newton on M (v1 - v0) = h f(x0 + h v1, v1), linearised at (xb, vb):
  //   (M - h D - h^2 K) dv = h f(xb, vb) + h K (x0 + h vb - xb) - M (vb - v0).
  // The first iteration linearises at (x0, v0): Baraff and Witkin's single solve.
  // line-search mode: Newton on the step's incremental potential (implicit_euler.hpp)
  if (m_newton) {
    m_newton->step(m_model, m_options, m_t + h, h, m_x, m_v, m_counters);
    m_contact_work += m_newton->contact_work();
    m_collider_work += m_newton->collider_work();
    m_contact_impulse += m_newton->contact_impulse();
    return;
  }
  const Model& m = m_model;
  const double drag = m.air_drag;
  m_x1 = m_x;  // xb
  m_v1 = m_v;  // vb
  for (int it = 0; it < m_options.newton_iterations; ++it) {
    ++m_counters.newton_iterations;
    ++m_counters.force_evals;
    linearize_springs(m.springs, m_x1, m_options.clamp_compressed, m_lin);
    // force at (xb, vb)
    m_force.setZero();
    add_spring_forces(m.springs, m_x1, m_v1, m_force, m_buf);
    for (int r = 0; r < 3; ++r) m_force.row(r) += m.gravity[r] * m.mass.transpose();
    m.add_drag(m_v1, m_force);
    // right-hand side
    m_rhs = h * m_force;
    // x0 + h vb - xb vanishes after the first iteration, where it is h v0
    if (it == 0) add_jacobian_product(m.springs, m_lin, m_v, h * h, 0.0, m_rhs, m_buf);
    for (int r = 0; r < 3; ++r)
      m_rhs.row(r) -= (m_v1.row(r) - m_v.row(r)).cwiseProduct(m.mass.transpose());
    // Jacobi preconditioner: inverse diagonal of A = M + h drag - h D - h^2 K
    for (int r = 0; r < 3; ++r) m_diag.row(r) = m.mass.transpose().array() + h * drag;
    add_jacobian_diagonal(m.springs, m_lin, -h * h, -h, m_diag, m_buf);
    m_diag = m_diag.cwiseInverse();
    auto apply = [&](const Matrix3X& u, Matrix3X& out) {
      for (int r = 0; r < 3; ++r)
        out.row(r) = u.row(r).cwiseProduct(m.mass.transpose()) + (h * drag) * u.row(r);
      add_jacobian_product(m.springs, m_lin, u, -h * h, -h, out, m_buf);
    };
    const CgResult cg = filtered_pcg(apply, m_rhs, m_diag, m.free, m_dv, m_cg,
                                     m_options.cg_tolerance, m_options.cg_max_iterations);
    m_counters.cg_iterations += cg.iterations;
    if (cg.relative_residual > m_options.cg_tolerance) ++m_counters.cg_unconverged;
    m_v1 += m_dv;
    m_x1 = m_x + h * m_v1;
  }
  m_x = m_x1;
  m_v = m_v1;
}

void MassSpringCloth::step_imex_euler(double h) {
  // Bullet 3.24's deformable explicit mode (btDeformableBodySolver with implicit = false):
  //   v* = v0 + h (M^-1 f_elastic(x0) + g)            springs and gravity explicit at x0
  //   (M - h D(x0)) dv = h D(x0) v*, v1 = v* + dv      dampers implicit, directions at x0
  //   x1 = x0 + h v1                                    symplectic position update
  // then air drag as the implicit sub-step v1 /= 1 + h drag / m that the Bullet adapters
  // apply after Bullet's step (Bullet's deformable world has no drag)
  const Model& m = m_model;
  ++m_counters.force_evals;
  linearize_springs(m.springs, m_x, false, m_lin);
  m_tmp.setZero();  // zero velocities: the elastic forces alone
  m_force.setZero();
  add_spring_forces(m.springs, m_x, m_tmp, m_force, m_buf);
  for (int r = 0; r < 3; ++r)
    m_v.row(r) +=
        h * (m_force.row(r).cwiseProduct(m.inv_mass.transpose()).array() + m.gravity[r]).matrix();
  if (m.any_held) m_v = (m.free.array() > 0.0).select(m_v, 0.0);
  // the damping solve, from dv = 0 as Bullet's conjugate gradient starts
  m_rhs.setZero();
  add_jacobian_product(m.springs, m_lin, m_v, 0.0, h, m_rhs, m_buf);
  for (int r = 0; r < 3; ++r) m_diag.row(r) = m.mass.transpose();
  add_jacobian_diagonal(m.springs, m_lin, 0.0, -h, m_diag, m_buf);
  m_diag = m_diag.cwiseInverse();
  auto apply = [&](const Matrix3X& u, Matrix3X& out) {
    for (int r = 0; r < 3; ++r) out.row(r) = u.row(r).cwiseProduct(m.mass.transpose());
    add_jacobian_product(m.springs, m_lin, u, 0.0, -h, out, m_buf);
  };
  const CgResult cg = filtered_pcg(apply, m_rhs, m_diag, m.free, m_dv, m_cg, m_options.cg_tolerance,
                                   m_options.cg_max_iterations);
  m_counters.cg_iterations += cg.iterations;
  if (cg.relative_residual > m_options.cg_tolerance) ++m_counters.cg_unconverged;
  m_v += m_dv;
  m_x += h * m_v;
  // m v' = m v - h drag (v' - wind), as the adapters solve it, free axes only
  if (m.air_drag != 0.0)
    for (Eigen::Index p = 0; p < m_v.cols(); ++p) {
      const double a = h * m.air_drag * m.inv_mass[p];
      const Vector3 dragged = (m_v.col(p) + a * m.wind) / (1.0 + a);
      m_v.col(p) = m.free.col(p).cwiseProduct(dragged) +
                   (Vector3::Ones() - m.free.col(p)).cwiseProduct(m_v.col(p));
    }
}

}  // namespace cloth
