#include "harness/scenario/scenario_writer.hpp"

#include <filesystem>
#include <initializer_list>
#include <sstream>

#include "format/number_format.hpp"
#include "harness/io/toml_text.hpp"
#include "harness/scenario/scenario_format.hpp"

namespace clothbench {

namespace {

using cloth::toml_double;

std::string vec(std::initializer_list<double> xs) {
  std::string s = "[";
  for (double x : xs) s += (s.size() > 1 ? ", " : "") + toml_double(x);
  return s + "]";
}

/// The keys of a custom engine.
void write_custom_options(std::ostream& o, const cloth::SolverOptions& so) {
  o << "integrator = " << toml_string(cloth::integrator_name(so.integrator)) << "\n"
    << "newton = " << toml_string(cloth::newton_method_name(so.newton)) << "\n"
    << "newton_iterations = " << so.newton_iterations << "\n"
    << "newton_tolerance = " << toml_double(so.newton_tolerance) << "  # m/s^2\n"
    << "linear_solver = " << toml_string(cloth::linear_solver_name(so.linear_solver)) << "\n"
    << "cg_tolerance = " << toml_double(so.cg_tolerance) << "\n"
    << "cg_max_iterations = " << so.cg_max_iterations << "\n"
    << "cg_forcing = " << toml_string(cloth::cg_forcing_name(so.cg_forcing)) << "\n"
    << "contacts = " << toml_string(cloth::contact_mode_name(so.contacts)) << "\n"
    << "clamp_compressed = " << (so.clamp_compressed ? "true" : "false") << "\n"
    << "substeps = " << so.substeps << "  # xpbd\n"
    << "iterations = " << so.iterations << "  # xpbd (per substep), projective\n";
  if (so.newton == cloth::NewtonMethod::line_search)
    o << "clamped_iterations = " << so.clamped_iterations << "\n";
}

std::string vec3(const cloth::Vector3& v) {
  return vec({v.x(), v.y(), v.z()});
}

/// The keys of a mujoco engine (margin and friction only when they replace the scene's).
void write_mujoco_options(std::ostream& o, const reference::MujocoOptions& m) {
  o << "integrator = " << toml_string(reference::mujoco_integrator_name(m.integrator)) << "\n";
  if (m.margin) o << "margin = " << toml_double(*m.margin) << "  # m\n";
  if (m.friction) o << "friction = " << toml_double(*m.friction) << "\n";
  o << "solref = " << vec({m.solref[0], m.solref[1]}) << "  # s, 1\n"
    << "solimp = " << vec({m.solimp[0], m.solimp[1], m.solimp[2]}) << "  # 1, 1, m\n"
    << "cone = " << toml_string(m.elliptic ? "elliptic" : "pyramidal") << "\n";
}

/// A motion's key: velocity (when allowed and there is no path) or path.
void write_motion(std::ostream& o, const cloth::Motion& m, bool velocity_key) {
  if (m.path.empty()) {
    if (velocity_key) o << "velocity = " << vec3(m.velocity) << "  # m/s\n";
    return;
  }
  o << "path = [";
  for (size_t k = 0; k < m.path.size(); ++k) {
    const auto& p = m.path[k];
    o << (k ? ", " : "") << vec({p[0], p[1], p[2], p[3]});
  }
  o << "]  # [s, m, m, m]\n";
}

/// The keys every collider has.
void write_collider(std::ostream& o, const cloth::Collider& c) {
  o << "restitution = " << toml_double(c.restitution) << "\n"
    << "friction = " << toml_double(c.friction) << "\n"
    << "margin = " << toml_double(c.margin) << "  # m\n";
  write_motion(o, c, true);
}

/// A selection's keys, as [[constraint]] and [[handle]] write them.
void write_selection(std::ostream& o, const ConstraintSpec& k) {
  o << "select = " << toml_string(k.select) << "\n";
  if (k.select == "disk")
    o << "center = " << vec({k.disk_center_x, k.disk_center_z}) << "  # m\n"
      << "radius = " << toml_double(k.disk_radius) << "  # m\n";
  if (k.select == "within")
    o << "center = " << vec3(k.center) << "  # m\nradius = " << toml_double(k.disk_radius)
      << "  # m\n";
  if (k.select == "box")
    o << "min = " << vec3(k.box_min) << "  # m\nmax = " << vec3(k.box_max) << "  # m\n";
  if (k.select == "group") o << "name = " << toml_string(k.group) << "\n";
  if (k.select == "indices" && !k.vertices.empty()) {
    o << "list = [";
    for (size_t p = 0; p < k.vertices.size(); ++p) o << (p ? ", " : "") << k.vertices[p];
    o << "]\n";
  } else if (k.select == "indices") {
    o << "list = [";
    for (size_t p = 0; p < k.indices.size(); ++p)
      o << (p ? ", " : "") << "[" << k.indices[p].first << ", " << k.indices[p].second << "]";
    o << "]\n";
  }
}

/// Handles, spheres and the other shapes.
void write_colliders(std::ostream& o, const Scenario& s) {
  for (const HandleSpec& h : s.handles) {
    o << "\n[[handle]]\n";
    write_selection(o, h.select);
    write_motion(o, h.motion, false);
  }
  for (const cloth::Sphere& sp : s.scene.spheres) {
    o << "\n[[sphere]]\ncenter = " << vec3(sp.center) << "  # m\n"
      << "radius = " << toml_double(sp.radius) << "  # m\n";
    write_collider(o, sp);
  }
  for (const cloth::HalfSpace& p : s.scene.shapes.planes) {
    o << "\n[[plane]]\npoint = " << vec3(p.point) << "  # m\nnormal = " << vec3(p.normal) << "\n";
    write_collider(o, p);
  }
  for (const cloth::Box& b : s.scene.shapes.boxes) {
    o << "\n[[box]]\ncenter = " << vec3(b.center) << "  # m\n"
      << "half_extents = " << vec3(b.half_extents) << "  # m\n";
    write_collider(o, b);
  }
  for (const cloth::Capsule& c : s.scene.shapes.capsules) {
    o << "\n[[capsule]]\na = " << vec3(c.a) << "  # m\nb = " << vec3(c.b) << "  # m\n"
      << "radius = " << toml_double(c.radius) << "  # m\n";
    write_collider(o, c);
  }
  for (const cloth::Cylinder& c : s.scene.shapes.cylinders) {
    o << "\n[[cylinder]]\ncenter = " << vec3(c.center) << "  # m\n"
      << "radius = " << toml_double(c.radius) << "  # m\nheight = " << toml_double(c.height)
      << "  # m\n";
    write_collider(o, c);
  }
}

/// [cloth]: the grid, or the mesh (its file's resolved path, or the [cloth.generate] table).
void write_cloth(std::ostream& o, const Scenario& s) {
  const auto d = [](double x) { return toml_double(x); };
  const cloth::ClothParams& c = s.scene.cloth;
  o << "\n[cloth]\n";
  if (!s.mesh.file.empty()) {
    o << "mesh = "
      << toml_string(std::filesystem::absolute(s.mesh.path).lexically_normal().string()) << "\n";
  } else if (!s.mesh.generated) {
    o << "particles = [" << c.nu << ", " << c.nv << "]\n"
      << "size = " << vec({c.size_u, c.size_v}) << "  # m\n"
      << "center = " << vec({c.center.x(), c.center.y(), c.center.z()}) << "  # m\n"
      << "plane = " << toml_string(plane_name(c.plane)) << "\n";
  }
  if (c.areal_density > 0)
    o << "areal_density = " << d(c.areal_density) << "  # kg/m^2\n";
  else if (c.total_mass > 0)
    o << "total_mass = " << d(c.total_mass) << "  # kg\n";
  else
    o << "particle_mass = " << d(c.particle_mass) << "  # kg\n";
  if (c.anisotropic())
    o << "stiffness = { structural_u = " << d(c.k_structural)
      << ", structural_v = " << d(c.structural_v());
  else
    o << "stiffness = { structural = " << d(c.k_structural);
  // shear springs: a grid's, or a generated grid lattice's
  const bool lattice = s.mesh.generated && s.mesh.shape.lattice == cloth::MeshLattice::grid;
  if (!s.mesh.any() || lattice) o << ", shear = " << d(c.k_shear);
  o << ", bend = " << d(c.k_bend) << " }  # N/m\n";
  if (c.bend_model == cloth::BendModel::hinge)
    o << "bend_model = \"hinge\"\nbending_rigidity = " << d(c.bending_rigidity) << "  # N m\n";
  o << "damping = " << d(c.damping) << "  # N s/m\n"
    << "air_drag = " << d(c.air_drag) << "  # N s/m\n"
    << "self_collision = " << (c.self_collision ? "true" : "false") << "\n"
    << "thickness = " << d(c.thickness) << "  # m\n"
    << "self_friction = " << d(c.self_friction) << "\n";
  if (!s.mesh.generated) return;
  const cloth::ShapeSpec& g = s.mesh.shape;
  o << "\n[cloth.generate]\nshape = " << toml_string(cloth::mesh_shape_name(g.shape)) << "\n";
  for (std::string_view key : shape_keys(g.shape)) {
    if (key == "radius") o << "radius = " << d(g.radius) << "  # m\n";
    if (key == "inner_radius") o << "inner_radius = " << d(g.inner_radius) << "  # m\n";
    if (key == "size") o << "size = " << vec({g.size_u, g.size_v}) << "  # m\n";
    if (key == "length") o << "length = " << d(g.length) << "  # m\n";
  }
  o << "edge_length = " << d(g.edge_length) << "  # m\n"
    << "seed = " << g.seed << "\n"
    << "center = " << vec3(g.center) << "  # m\n"
    << "plane = " << toml_string(plane_name(g.plane)) << "\n";
  if (g.lattice == cloth::MeshLattice::grid)
    o << "lattice = \"grid\"\nlattice_angle = " << d(g.lattice_angle) << "  # degrees\n";
}

}  // namespace

std::string scenario_to_toml(const Scenario& s) {
  std::ostringstream o;
  const auto d = [](double x) { return toml_double(x); };
  o << "# the fully resolved scenario: every key, with defaults and overrides filled in\n"
    << "name = " << toml_string(s.name) << "\n"
    << "description = " << toml_string(s.description) << "\n"
    << "duration = " << d(s.duration) << "  # s\n"
    << "frame_interval = " << d(s.frame_interval) << "  # s\n"
    << "snapshot_interval = " << d(s.snapshot_interval) << "  # s\n"
    << "animation_interval = " << d(s.animation_interval) << "  # s\n"
    << "blowup_strain = " << d(s.blowup_strain) << "\n"
    << "blowup_energy = " << d(s.blowup_energy) << "\n"
    << "reference = "
    << toml_string(!s.reference.empty() || s.engines.empty() ? s.reference : s.engines.front().name)
    << "\n";
  const cloth::Vector3& g = s.scene.gravity;
  o << "gravity = " << vec({g.x(), g.y(), g.z()}) << "  # m/s^2\n"
    << "wind = " << vec3(s.scene.wind) << "  # m/s\n";

  write_cloth(o, s);

  for (const ConstraintSpec& k : s.constraints) {
    o << "\n[[constraint]]\n";
    write_selection(o, k);
    o << "hold = " << toml_string(hold_letters(k.hold)) << "\n";
  }
  write_colliders(o, s);
  if (!s.test.kind.empty()) o << "\n[test]\nkind = " << toml_string(s.test.kind) << "\n";
  if (s.test.kind == "cantilever") o << "edge = " << d(s.test.edge) << "  # m\n";
  if (s.test.kind == "cantilever" && s.test.overhang_rule != "fixed")
    o << "overhang_rule = " << toml_string(s.test.overhang_rule) << "\n";
  if (s.test.kind == "strip-tensile")
    o << "direction = " << toml_string(s.test.direction)
      << "\nfit_strain = " << d(s.test.fit_strain) << "\n";
  if (s.test.kind == "bias-extension")
    o << "fit_angle = " << d(s.test.fit_angle) << "  # degrees\n";

  for (const EngineSpec& e : s.engines) {
    o << "\n[[engine]]\n"
      << "name = " << toml_string(e.name) << "\n"
      << "kind = " << toml_string(engine_kind_name(e.kind)) << "\n"
      << "dt = " << d(e.dt) << "  # s\n";
    if (e.self_collision)
      o << "self_collision = " << (*e.self_collision ? "true" : "false") << "\n";
    // the engine's own scene keys, as the file gave them
    if (!e.overrides.empty()) {
      o << "overrides = { ";
      for (size_t k = 0; k < e.overrides.size(); ++k)
        o << (k ? ", " : "") << toml_string(e.overrides[k].first) << " = " << e.overrides[k].second;
      o << " }\n";
    }
    if (e.kind == EngineKind::custom) {
      write_custom_options(o, e.solver);
    } else if (e.kind == EngineKind::bullet_deformable) {
      o << "implicit = " << (e.bullet.implicit ? "true" : "false") << "\n"
        << "line_search = " << (e.bullet.line_search ? "true" : "false") << "\n"
        << "projection = " << (e.bullet.projection ? "true" : "false") << "\n"
        << "repulsion_stiffness = " << d(e.bullet.repulsion_stiffness) << "  # N/m\n"
        << "collision_margin = " << d(e.bullet.collision_margin) << "  # m\n";
    } else if (e.kind == EngineKind::bullet_softbody) {
      o << "stiffness = " << toml_string(reference::softbody_stiffness_name(e.bullet.stiffness))
        << "\n"
        << "klst = " << d(e.bullet.klst) << "\n"
        << "iterations = " << e.bullet.iterations << "\n";
    } else if (e.kind == EngineKind::mujoco) {
      write_mujoco_options(o, e.mujoco);
    } else if (e.kind == EngineKind::external) {
      o << "command = [";
      for (size_t k = 0; k < e.external.command.size(); ++k)
        o << (k ? ", " : "") << toml_string(e.external.command[k]);
      o << "]\nstep_timeout = " << d(e.external.step_timeout) << "  # s\n";
      // written when set only: a sweep written before the key resumes as before
      if (e.external.share_cpu) o << "share_cpu = true\n";
    }
  }
  return o.str();
}

}  // namespace clothbench
