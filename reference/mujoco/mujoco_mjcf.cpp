#include "reference/mujoco/mujoco_mjcf.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace clothbench::reference {

namespace {

/// x with every digit a double has, so that the model holds the scene's numbers exactly.
std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

/// "x y z" of v.
std::string vec(const cloth::Vector3& v) {
  return num(v.x()) + " " + num(v.y()) + " " + num(v.z());
}

/// The contact margin of collider c under options (m).
double margin_of(const cloth::Collider& c, const MujocoOptions& options) {
  return options.margin.value_or(c.margin);
}

/// Calls visit(collider, shape attributes, position at t = 0) for every collider of model:
/// spheres, planes, boxes, capsules, cylinders, in that order.
template <class Visit>
void for_each_collider(const cloth::Model& model, Visit&& visit) {
  for (const cloth::Sphere& s : model.spheres)
    visit(s, "type=\"sphere\" size=\"" + num(s.radius) + "\"", s.center);
  for (const cloth::HalfSpace& h : model.shapes.planes)
    visit(h, "type=\"plane\" size=\"0 0 1\" zaxis=\"" + vec(h.normal) + "\"", h.point);
  for (const cloth::Box& b : model.shapes.boxes)
    visit(b, "type=\"box\" size=\"" + vec(b.half_extents) + "\"", b.center);
  for (const cloth::Capsule& c : model.shapes.capsules) {
    const cloth::Vector3 mid = 0.5 * (c.a + c.b);
    visit(c,
          "type=\"capsule\" size=\"" + num(c.radius) + "\" fromto=\"" + vec(c.a - mid) + " " +
              vec(c.b - mid) + "\"",
          mid);
  }
  // MuJoCo's cylinder has its axis along z, the scene's along y
  for (const cloth::Cylinder& c : model.shapes.cylinders)
    visit(c,
          "type=\"cylinder\" size=\"" + num(c.radius) + " " + num(0.5 * c.height) +
              "\" zaxis=\"0 1 0\"",
          c.center);
}

/// The option, size and default elements.
void write_header(std::ostringstream& s, const cloth::Model& model, const MujocoOptions& o,
                  double dt, const MujocoSize& size) {
  static const char* const integrators[] = {"Euler", "RK4", "implicit"};
  s << "<mujoco model=\"clothbench\">\n";
  s << "<compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n";
  s << "<option timestep=\"" << num(dt) << "\" gravity=\"" << vec(model.gravity)
    << "\" integrator=\"" << integrators[static_cast<int>(o.integrator)] << "\" cone=\""
    << (o.elliptic ? "elliptic" : "pyramidal") << "\"/>\n";
  s << "<size nconmax=\"" << size.contacts << "\" njmax=\"" << size.rows << "\" nstack=\""
    << size.stack << "\"/>\n";
  s << "<default><geom solref=\"" << num(o.solref[0]) << " " << num(o.solref[1]) << "\" solimp=\""
    << num(o.solimp[0]) << " " << num(o.solimp[1]) << " " << num(o.solimp[2]) << "\"/></default>\n";
}

/// The colliders: geoms in the world, or in mocap bodies when they move.
void write_colliders(std::ostringstream& s, const cloth::Model& model, const MujocoOptions& o,
                     MjcfLayout& layout) {
  for_each_collider(
      model, [&](const cloth::Collider& c, const std::string& shape, const cloth::Vector3& at) {
        const double mu = o.friction.value_or(c.friction);
        // the particle sphere covers particle_radius of the margin, the geom margin the rest
        const std::string geom = "<geom " + shape + " contype=\"0\" conaffinity=\"1\" condim=\"" +
                                 (mu > 0 ? "3" : "1") + "\" friction=\"" + num(mu) +
                                 " 0.005 0.0001\" margin=\"" +
                                 num(margin_of(c, o) - layout.particle_radius) + "\"";
        if (!c.moves()) {
          s << geom << " pos=\"" << vec(at) << "\"/>\n";
          return;
        }
        layout.moving.push_back(&c);
        layout.moving_start.push_back(at);
        s << "<body mocap=\"true\" pos=\"" << vec(at) << "\">" << geom << "/></body>\n";
      });
}

/// The particles' bodies, and the handles' mocap bodies after the moving colliders'; each slide
/// joint damped by joint_damping (N s/m; none when 0).
void write_particles(std::ostringstream& s, const cloth::Model& model, double joint_damping,
                     MjcfLayout& layout) {
  int qpos = 0;
  int mocap = static_cast<int>(layout.moving.size());
  static const char* const axes[] = {"1 0 0", "0 1 0", "0 0 1"};
  for (int p = 0; p < model.particle_count(); ++p) {
    const std::string site = "<site name=\"p" + std::to_string(p) + "\"/>";
    const cloth::Vector3 x0 = model.x0.col(p);
    if (layout.handle_of[size_t(p)] >= 0) {
      layout.particle_mocap[size_t(p)] = mocap++;
      s << "<body mocap=\"true\" pos=\"" << vec(x0) << "\">" << site << "</body>\n";
      continue;
    }
    s << "<body pos=\"" << vec(x0) << "\">";
    bool moves = false;
    for (int a = 0; a < 3; ++a) {
      if (model.free(a, p) == 0.0) continue;
      layout.dof[size_t(p)][size_t(a)] = qpos++;
      s << "<joint type=\"slide\" axis=\"" << axes[a] << "\"";
      if (joint_damping > 0.0) s << " damping=\"" << num(joint_damping) << "\"";
      s << "/>";
      moves = true;
    }
    // a pinned particle is part of the world: no mass, no geom
    if (moves)
      s << "<inertial pos=\"0 0 0\" mass=\"" << num(model.mass[p])
        << "\" diaginertia=\"1 1 1\"/><geom type=\"sphere\" size=\"" << num(layout.particle_radius)
        << "\" contype=\"1\" conaffinity=\"0\" condim=\"1\" friction=\"0 0 0\"/>";
    s << site << "</body>\n";
  }
}

/// One spatial tendon per spring, in the order of links().
void write_tendons(std::ostringstream& s, const cloth::Model& model) {
  s << "<tendon>\n";
  for (const cloth::SpringLink& l : model.springs.links())
    s << "<spatial stiffness=\"" << num(l.stiffness) << "\" damping=\""
      << num(model.springs.damping) << "\" springlength=\"" << num(l.rest) << "\"><site site=\"p"
      << l.a << "\"/><site site=\"p" << l.b << "\"/></spatial>\n";
  s << "</tendon>\n";
}

}  // namespace

MjcfLayout mjcf_layout(const cloth::Model& model) {
  const auto n = static_cast<size_t>(model.particle_count());
  MjcfLayout layout;
  layout.dof.assign(n, {-1, -1, -1});
  layout.particle_mocap.assign(n, -1);
  layout.handle_of.assign(n, -1);
  for (size_t h = 0; h < model.handles.size(); ++h)
    for (int p : model.handles[h].particles) layout.handle_of[size_t(p)] = static_cast<int>(h);
  return layout;
}

bool air_drag_in_joints(const MujocoOptions& options) {
  return options.integrator == MujocoIntegrator::rk4;
}

std::string mujoco_mjcf(const cloth::Model& model, const MujocoOptions& options, double dt,
                        const MujocoSize& size, MjcfLayout& layout) {
  // the particle spheres: half the smallest margin, the colliders' geom margins the rest
  double smallest = options.margin.value_or(1e300);
  for_each_collider(model,
                    [&](const cloth::Collider& c, const std::string&, const cloth::Vector3&) {
                      smallest = std::min(smallest, margin_of(c, options));
                    });
  layout.particle_radius = smallest < 1e300 ? 0.5 * smallest : 0.005;
  std::ostringstream s;
  write_header(s, model, options, dt, size);
  s << "<worldbody>\n";
  write_colliders(s, model, options, layout);
  write_particles(s, model, air_drag_in_joints(options) ? model.air_drag : 0.0, layout);
  s << "</worldbody>\n";
  write_tendons(s, model);
  s << "</mujoco>\n";
  return s.str();
}

}  // namespace clothbench::reference
