#include "harness/scenario/scenario_loader.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "cloth/contact/self_contact.hpp"
#include "cloth/model/model.hpp"
#include "format/number_format.hpp"
#include "harness/scenario/cloth_reader.hpp"
#include "harness/scenario/embedded_seed_scenario.hpp"
#include "harness/scenario/engine_refusal.hpp"
#include "harness/scenario/scenario_overrides.hpp"
#include "harness/scenario/selection_reader.hpp"
#include "harness/scenario/test_reader.hpp"
#include "harness/scenario/toml_reader.hpp"

namespace clothbench {

namespace {

// ---- reading a toml::table into a Scenario, with located errors

/// A path = [[t, dx, dy, dz], ...]: times strictly increasing from 0, no displacement at 0.
std::vector<std::array<double, 4>> read_path(const Reader& r, const At& at) {
  const toml::node* n = at.table.get("path");
  const toml::array* a = n->as_array();
  if (!a || a->empty()) r.expected(*n, at.key("path"), "a non-empty array of [t, dx, dy, dz]");
  std::vector<std::array<double, 4>> path;
  for (size_t k = 0; k < a->size(); ++k) {
    const toml::node& e = *a->get(k);
    const std::string key = at.key("path") + "." + std::to_string(k);
    const toml::array* row = e.as_array();
    std::array<double, 4> p{};
    for (size_t c = 0; row && row->size() == 4 && c < 4; ++c) {
      const toml::node& x = *row->get(c);
      const auto v =
          x.is_integer() ? std::optional<double>(double(x.as_integer()->get())) : x.value<double>();
      if (!v || !std::isfinite(*v))
        row = nullptr;
      else
        p[c] = *v;
    }
    if (!row || row->size() != 4) r.expected(e, key, "[t, dx, dy, dz], 4 numbers (s, m, m, m)");
    if (k == 0 && (p[0] != 0 || p[1] != 0 || p[2] != 0 || p[3] != 0))
      r.expected(e, key, "the first point at [0, 0, 0, 0] (no displacement at t = 0)");
    if (k > 0 && !(p[0] > path.back()[0]))
      r.fail(&e, key,
             "expected times strictly increasing, got t = " + toml_double(p[0]) +
                 " s after t = " + toml_double(path.back()[0]) + " s");
    path.push_back(p);
  }
  return path;
}

/// A velocity or a path, never both.
cloth::Motion read_motion(const Reader& r, const At& at, bool velocity_key) {
  cloth::Motion m;
  const toml::node* v = velocity_key ? at.table.get("velocity") : nullptr;
  const toml::node* p = at.table.get("path");
  if (v && p)
    r.fail(p, at.key("path"), "expected velocity or path, got both (give the motion one way)");
  if (velocity_key) m.velocity = r.vec3(at, "velocity", m.velocity);
  if (p) m.path = read_path(r, at);
  return m;
}

/// The keys every collider has.
void read_collider(const Reader& r, const At& at, cloth::Collider& c) {
  static_cast<cloth::Motion&>(c) = read_motion(r, at, true);
  c.restitution = r.number(at, "restitution", c.restitution, kUnitInterval);
  c.friction = r.number(at, "friction", c.friction, kNonNegative);
  c.margin = r.number(at, "margin", c.margin, kShell);
}

/// Checks t's keys against a shape's own keys and the colliders' common ones.
void check_shape_keys(const Reader& r, const At& at, const Keys& own) {
  Keys keys = own;
  keys.insert(keys.end(), kColliderKeys.begin(), kColliderKeys.end());
  r.check_keys(at, keys);
}

cloth::Sphere read_sphere(const Reader& r, const toml::table& t, const std::string& path) {
  const At at{t, path};
  r.check_keys(at, kSphereKeys);
  cloth::Sphere s;
  s.center = r.vec3(at, "center", s.center);
  s.radius = r.number(at, "radius", s.radius, kLength);
  read_collider(r, at, s);
  return s;
}

cloth::HalfSpace read_plane(const Reader& r, const toml::table& t, const std::string& path) {
  const At at{t, path};
  check_shape_keys(r, at, kPlaneKeys);
  cloth::HalfSpace s;
  s.point = r.vec3(at, "point", s.point);
  s.normal = r.vec3(at, "normal", s.normal);
  if (!(s.normal.norm() > 0) || !std::isfinite(s.normal.norm()))
    r.expected(*t.get("normal"), at.key("normal"), "a non-zero normal (out of the solid)");
  read_collider(r, at, s);
  return s;
}

cloth::Box read_box(const Reader& r, const toml::table& t, const std::string& path) {
  const At at{t, path};
  check_shape_keys(r, at, kBoxKeys);
  cloth::Box s;
  s.center = r.vec3(at, "center", s.center);
  s.half_extents = r.vec3(at, "half_extents", s.half_extents, kLength);
  read_collider(r, at, s);
  return s;
}

cloth::Capsule read_capsule(const Reader& r, const toml::table& t, const std::string& path) {
  const At at{t, path};
  check_shape_keys(r, at, kCapsuleKeys);
  cloth::Capsule s;
  s.a = r.vec3(at, "a", s.a);
  s.b = r.vec3(at, "b", s.b);
  if (!((s.b - s.a).squaredNorm() > 0))
    r.fail(t.get("b") ? t.get("b") : &t, at.key("b"),
           "expected b different from a (a capsule's axis), got both at [" + toml_double(s.a.x()) +
               ", " + toml_double(s.a.y()) + ", " + toml_double(s.a.z()) + "]");
  s.radius = r.number(at, "radius", s.radius, kLength);
  read_collider(r, at, s);
  return s;
}

cloth::Cylinder read_cylinder(const Reader& r, const toml::table& t, const std::string& path) {
  const At at{t, path};
  check_shape_keys(r, at, kCylinderKeys);
  cloth::Cylinder s;
  s.center = r.vec3(at, "center", s.center);
  s.radius = r.number(at, "radius", s.radius, kLength);
  s.height = r.number(at, "height", s.height, kLength);
  read_collider(r, at, s);
  return s;
}

/// Every [[key]] table read by read.
template <class T, class Read>
std::vector<T> read_all(const Reader& r, const toml::table& root, const char* key, Read read) {
  std::vector<T> out;
  const auto tables = r.tables({root, ""}, key);
  for (size_t k = 0; k < tables.size(); ++k)
    out.push_back(read(r, *tables[k], std::string(key) + "." + std::to_string(k)));
  return out;
}

/// The engine's name, kind and integrator; messages name it by index until its name is valid.
EngineSpec read_engine_identity(const Reader& r, const toml::table& t, int index) {
  EngineSpec e;
  const toml::node* name = t.get("name");
  std::string path = "engine." + std::to_string(index);
  if (name) {
    const std::string s = r.string({t, path}, "name", "");
    if (!valid_engine_name(s))
      r.expected(*name, path + ".name", "a name of letters, digits, '-', '_' or '+'");
    path = "engine." + s;
  }
  const At first{t, path};
  e.kind =
      *parse_engine_kind(r.choice(first, "kind", engine_kind_name(e.kind), engine_kind_names()));
  if (engine_kind_info(e.kind).has_integrators) {
    const std::string integrator = r.choice(
        first, "integrator", cloth::integrator_name(e.solver.integrator), integrator_names());
    e.solver.integrator = *cloth::parse_integrator(integrator);
  }
  e.name = name ? name->as_string()->get() : derived_engine_name(e.kind, e.solver.integrator);
  return e;
}

/// Refuses keys of t that engine e's kind does not have; keys of another kind are named so.
void check_engine_keys(const Reader& r, const toml::table& t, const EngineSpec& e) {
  const At at{t, "engine." + e.name};
  const EngineKindInfo& own = engine_kind_info(e.kind);
  Keys known = kEngineCommonKeys;
  known.insert(known.end(), own.keys.begin(), own.keys.end());
  const toml::node* kind = t.get("kind");
  const std::string kind_source = from_override(kind) ? " (" + *kind->source().path + ")" : "";
  for (const auto& [k, v] : t) {
    if (contains(known, k.str())) continue;
    for (const EngineKindInfo& other : engine_kind_table())
      if (contains(other.keys, k.str()))
        r.fail(&v, at.key(k.str()),
               "applies only to " + std::string(other.name) + " engines, this one is " + own.name +
                   kind_source);
    r.fail(&v, at.key(k.str()), "unknown key" + suggest(k.str(), known));
  }
}

/// A choice whose value only is what newton = "line-search" or "trust-region" alone can do: its
/// default there, `otherwise` in linearized mode, where only is refused (why says why).
std::string read_line_search_choice(const Reader& r, const At& at, const cloth::SolverOptions& o,
                                    const char* key, const Keys& choices, const char* only,
                                    const char* otherwise, const char* why) {
  const bool line_search = cloth::minimizes_potential(o.newton);
  std::string value = r.choice(at, key, line_search ? only : otherwise, choices);
  if (value == only && !line_search)
    r.fail(at.table.get(key), at.key(key),
           "\"" + value + "\" needs newton = \"line-search\" or \"trust-region\" (" + why + ")");
  return value;
}

/// cg_forcing and contacts: adaptive forcing and the barrier by default with line-search and
/// trust-region.
void read_line_search_keys(const Reader& r, const At& at, cloth::SolverOptions& o) {
  o.cg_forcing = *cloth::parse_cg_forcing(read_line_search_choice(
      r, at, o, "cg_forcing", kCgForcings, cloth::cg_forcing_name(cloth::CgForcing::adaptive),
      cloth::cg_forcing_name(cloth::CgForcing::fixed),
      "the linearized step has no Newton residual to adapt to"));
  // the barrier by default with line-search and trust-region; in-solve and barrier need one
  const bool line_search = cloth::minimizes_potential(o.newton);
  const cloth::ContactMode fallback =
      line_search ? cloth::kScenarioLineSearchContacts : cloth::ContactMode::after_step;
  const std::string value =
      r.choice(at, "contacts", cloth::contact_mode_name(fallback), kContactModes);
  o.contacts = *cloth::parse_contact_mode(value);
  if (o.contacts != cloth::ContactMode::after_step && !line_search)
    r.fail(at.table.get("contacts"), at.key("contacts"),
           "\"" + value +
               "\" needs newton = \"line-search\" or \"trust-region\" (the linearized step "
               "resolves contacts after the step)");
}

/// The mujoco engine's options; unset margin and friction stay the scene's.
void read_mujoco_options(const Reader& r, const At& at, reference::MujocoOptions& o) {
  o.integrator = *reference::parse_mujoco_integrator(r.choice(
      at, "integrator", reference::mujoco_integrator_name(o.integrator), kMujocoIntegrators));
  if (at.table.get("margin")) o.margin = r.number(at, "margin", 0.0, kPositive);
  if (at.table.get("friction")) o.friction = r.number(at, "friction", 0.0, kNonNegative);
  // [time constant (s), damping ratio]
  o.solref = r.number_pair(at, "solref", o.solref, kPositive);
  const cloth::Vector3 imp =
      r.vec3(at, "solimp", cloth::Vector3(o.solimp[0], o.solimp[1], o.solimp[2]));
  if (!(imp[0] > 0 && imp[0] < 1 && imp[1] > 0 && imp[1] < 1 && imp[2] > 0))
    r.fail(at.table.get("solimp"), at.key("solimp"),
           "expected [d0, dwidth, width] with d0 and dwidth in (0, 1) and width > 0 m");
  o.solimp = {imp[0], imp[1], imp[2]};
  o.elliptic = r.choice(at, "cone", "pyramidal", {"pyramidal", "elliptic"}) == "elliptic";
}

/// external: the command, a non-empty array of non-empty strings, the time budget and whether
/// it shares the run's CPU.
void read_external_options(const Reader& r, const At& at, reference::ExternalOptions& o) {
  const toml::node* n = at.table.get("command");
  if (!n) r.fail(&at.table, at.key("command"), "an external engine needs a command");
  const toml::array* a = n->as_array();
  for (size_t k = 0; a && k < a->size(); ++k) {
    const auto* s = a->get(k)->as_string();
    if (!s || s->get().empty()) a = nullptr;
    if (a) o.command.push_back(s->get());
  }
  if (!a || a->empty()) r.expected(*n, at.key("command"), "a non-empty array of non-empty strings");
  o.step_timeout = r.number(at, "step_timeout", o.step_timeout, kPositive);
  o.share_cpu = r.boolean(at, "share_cpu", o.share_cpu);
}

/// The command's words that name a file or folder relative to the scenario file's folder,
/// resolved against it (the program's name and its arguments alike; absolute paths, words
/// that start with '-' and words naming nothing there are kept as written).
void resolve_external_command(reference::ExternalOptions& o, const std::string& source) {
  namespace fs = std::filesystem;
  const fs::path base = fs::path(source).parent_path();
  for (std::string& word : o.command) {
    const fs::path p(word);
    std::error_code ec;
    if (word[0] == '-' || p.is_absolute() || base.empty() || !fs::exists(base / p, ec)) continue;
    word = fs::absolute(base / p, ec).lexically_normal().string();
  }
}

/// The options of e's kind, read from t.
void read_engine_options(const Reader& r, const At& at, EngineSpec& e) {
  switch (e.kind) {
    case EngineKind::custom: {
      cloth::SolverOptions& o = e.solver;
      // implicit-euler's default is line-search; the key is inert for the other integrators,
      // which keep the linearized default (so a sweep that swaps in implicit-euler gets it)
      const bool implicit = o.integrator == cloth::Integrator::implicit_euler;
      o.newton = *cloth::parse_newton_method(r.choice(
          at, "newton", cloth::newton_method_name(implicit ? cloth::kScenarioNewton : o.newton),
          kNewtonMethods));
      // line-search and trust-region: iterations are a limit and linear solves may be inexact
      const bool line_search = cloth::minimizes_potential(o.newton);
      const bool trust_region = o.newton == cloth::NewtonMethod::trust_region;
      const int newton_default =
          line_search ? cloth::kLineSearchNewtonIterations : o.newton_iterations;
      const double cg_default = line_search ? cloth::kLineSearchCgTolerance : o.cg_tolerance;
      o.newton_iterations = r.integer(at, "newton_iterations", newton_default, 1);
      o.newton_tolerance = r.number(at, "newton_tolerance", o.newton_tolerance, kPositive);
      o.linear_solver = *cloth::parse_linear_solver(r.choice(
          at, "linear_solver", cloth::linear_solver_name(o.linear_solver), kLinearSolvers));
      o.cg_tolerance = r.number(at, "cg_tolerance", cg_default, kPositive);
      if (trust_region && o.linear_solver == cloth::LinearSolver::ldlt)
        r.fail(at.table.get("linear_solver"), at.key("linear_solver"),
               "\"ldlt\" cannot solve newton = \"trust-region\"'s subproblems (they need a "
               "conjugate-gradient solver: auto, cg, block-jacobi-cg or two-level-cg)");
      o.cg_max_iterations = r.integer(at, "cg_max_iterations", o.cg_max_iterations, 1);
      read_line_search_keys(r, at, o);
      o.clamp_compressed = r.boolean(at, "clamp_compressed", o.clamp_compressed);
      o.clamped_iterations = r.integer(at, "clamped_iterations", o.clamped_iterations, 0);
      if (at.table.get("clamped_iterations") && o.newton != cloth::NewtonMethod::line_search)
        r.fail(at.table.get("clamped_iterations"), at.key("clamped_iterations"),
               "clamped_iterations needs newton = \"line-search\" (the linearized step always "
               "uses the clamped matrix, trust-region always the exact one)");
      // each step costs substeps x iterations sweeps: bounded so that a step always ends
      o.substeps = r.integer(at, "substeps", o.substeps, 1, kMaxSolverIterations);
      o.iterations = r.integer(at, "iterations", o.iterations, 1, kMaxSolverIterations);
      break;
    }
    case EngineKind::bullet_deformable: {
      reference::BulletOptions& o = e.bullet;
      o.implicit = r.boolean(at, "implicit", o.implicit);
      o.line_search = r.boolean(at, "line_search", o.line_search);
      o.projection = r.boolean(at, "projection", o.projection);
      o.repulsion_stiffness = r.number(at, "repulsion_stiffness", o.repulsion_stiffness, kPositive);
      o.collision_margin = r.number(at, "collision_margin", o.collision_margin, kNonNegative);
      break;
    }
    case EngineKind::bullet_softbody: {
      reference::BulletOptions& o = e.bullet;
      o.stiffness = *reference::parse_softbody_stiffness(r.choice(
          at, "stiffness", reference::softbody_stiffness_name(o.stiffness), kSoftbodyStiffness));
      o.klst = r.number(at, "klst", o.klst, kUnitInterval);
      o.iterations = r.integer(at, "iterations", o.iterations, 1);
      break;
    }
    case EngineKind::mujoco:
      read_mujoco_options(r, at, e.mujoco);
      break;
    case EngineKind::external:
      read_external_options(r, at, e.external);
      break;
  }
}

/// An [[engine]] table, the index-th.
EngineSpec read_engine(const Reader& r, const toml::table& t, int index) {
  EngineSpec e = read_engine_identity(r, t, index);
  check_engine_keys(r, t, e);
  const At at{t, "engine." + e.name};
  e.dt = r.number(at, "dt", e.dt, kPositive);
  if (t.get("self_collision")) e.self_collision = r.boolean(at, "self_collision", false);
  if (e.self_collision.value_or(false) && e.kind == EngineKind::bullet_softbody)
    r.fail(t.get("self_collision"), at.key("self_collision"), kSoftbodyNoSelfCollision);
  if (e.self_collision.value_or(false) && e.kind == EngineKind::mujoco)
    r.fail(t.get("self_collision"), at.key("self_collision"), kMujocoNoSelfCollision);
  read_engine_options(r, at, e);
  return e;
}

/// Reads an optional interval key (s) that must be 0 or a whole multiple of frame_interval.
double read_frame_multiple(const Reader& r, const toml::table& root, const std::string& key,
                           double def, double frame_interval) {
  const double v = r.number(At{root, ""}, key, def, kNonNegative);
  if (v > 0 && !whole_multiple(v, frame_interval)) {
    const auto [n, blamed] =
        blame({{root.get(key), key}, {root.get("frame_interval"), "frame_interval"}});
    r.fail(n, blamed,
           "expected " + key + " to be 0 or a whole multiple of frame_interval = " +
               toml_double(frame_interval) + " s, got " + key + " = " + toml_double(v) + " s");
  }
  return v;
}

/// The top-level timing and naming keys.
void read_header(const Reader& r, const toml::table& root, Scenario& s) {
  const At at{root, ""};
  s.name = r.string(at, "name", s.name);
  if (!valid_scenario_name(s.name))
    r.expected(*root.get("name"), "name",
               "a name of letters, digits, '-', '_' or '.' (it names the output folder)");
  s.description = r.string(at, "description", s.description);
  s.duration = r.number(at, "duration", s.duration, kPositive);
  s.frame_interval = r.number(at, "frame_interval", s.frame_interval, kPositive);
  if (!whole_multiple(s.duration, s.frame_interval)) {
    // a fractional last frame would be rounded away: the run would not last `duration`
    const auto [n, key] =
        blame({{root.get("duration"), "duration"}, {root.get("frame_interval"), "frame_interval"}});
    r.fail(n, key,
           "expected duration to be a whole multiple of frame_interval = " +
               toml_double(s.frame_interval) + " s, got duration = " + toml_double(s.duration) +
               " s");
  }
  if (s.duration / s.frame_interval > kMaxFrames) {
    const auto [n, key] =
        blame({{root.get("frame_interval"), "frame_interval"}, {root.get("duration"), "duration"}});
    r.fail(n, key,
           "expected at most " + cloth::shortest_decimal(kMaxFrames) +
               " frames, got duration / frame_interval = " +
               cloth::shortest_decimal(s.duration / s.frame_interval));
  }
  s.snapshot_interval =
      read_frame_multiple(r, root, "snapshot_interval", s.snapshot_interval, s.frame_interval);
  // left out: 1/30 s rounded to a whole number of frames (at least one)
  const long long frames = std::max(1LL, std::llround(1.0 / 30.0 / s.frame_interval));
  s.animation_interval = read_frame_multiple(r, root, "animation_interval",
                                             double(frames) * s.frame_interval, s.frame_interval);
  s.blowup_strain = r.number(at, "blowup_strain", s.blowup_strain, kPositive);
  s.blowup_energy = r.number(at, "blowup_energy", s.blowup_energy, kPositive);
}

/// The [[handle]] tables: their particles, each in one handle and no [[constraint]].
void read_handles(const Reader& r, const toml::table& root, Scenario& s) {
  const auto tables = r.tables({root, ""}, "handle");
  std::vector<int> owner(static_cast<size_t>(s.scene.particle_count()), -1);
  std::vector<std::vector<std::uint8_t>> held_by;  // each constraint's mask
  for (const ConstraintSpec& c : s.constraints) held_by.push_back(held_mask(s.scene, {c}));
  for (size_t k = 0; k < tables.size(); ++k) {
    const std::string path = "handle." + std::to_string(k);
    const At at{*tables[k], path};
    HandleSpec h;
    h.select = read_selection(r, *tables[k], path, s.scene, kHandleKeys);
    h.motion = read_motion(r, at, false);
    cloth::Handle handle;
    handle.motion = h.motion;
    const std::vector<std::uint8_t> mask = held_mask(s.scene, {h.select});
    for (size_t p = 0; p < mask.size(); ++p) {
      if (!mask[p]) continue;
      const std::string which = s.scene.mesh
                                    ? "vertex " + std::to_string(p)
                                    : "particle (" + std::to_string(p % size_t(s.scene.cloth.nu)) +
                                          ", " + std::to_string(p / size_t(s.scene.cloth.nu)) + ")";
      const toml::node* blame_at = tables[k]->get("select") ? tables[k]->get("select") : tables[k];
      for (size_t c = 0; c < s.constraints.size(); ++c)
        if (held_by[c][p])
          r.fail(blame_at, at.key("select"),
                 "expected particles no [[constraint]] holds, got " + which +
                     ", which constraint." + std::to_string(c) + " holds too");
      if (owner[p] >= 0)
        r.fail(blame_at, at.key("select"),
               "expected particles no other handle moves, got " + which + ", which handle." +
                   std::to_string(owner[p]) + " moves too");
      owner[p] = static_cast<int>(k);
      handle.particles.push_back(static_cast<int>(p));
    }
    s.handles.push_back(std::move(h));
    s.scene.handles.push_back(std::move(handle));
  }
}

/// Gravity, wind, the cloth, its constraints and handles, and the colliders.
void read_scene(const Reader& r, const toml::table& root, Scenario& s) {
  const At at{root, ""};
  s.scene.gravity = r.vec3(at, "gravity", s.scene.gravity, kAcceleration);
  read_cloth(r, r.table(at, "cloth"), s);
  s.scene.wind = r.vec3(at, "wind", s.scene.wind);
  if (!s.scene.wind.isZero() && s.scene.cloth.air_drag == 0.0)
    r.fail(root.get("wind"), "wind",
           "expected cloth.air_drag > 0 with a wind (without air drag the wind does nothing)");
  const auto constraints = r.tables(at, "constraint");
  for (size_t k = 0; k < constraints.size(); ++k)
    s.constraints.push_back(read_selection(r, *constraints[k], "constraint." + std::to_string(k),
                                           s.scene, kConstraintKeys));
  s.scene.held = held_mask(s.scene, s.constraints);
  read_handles(r, root, s);
  s.scene.spheres = read_all<cloth::Sphere>(r, root, "sphere", read_sphere);
  s.scene.shapes.planes = read_all<cloth::HalfSpace>(r, root, "plane", read_plane);
  s.scene.shapes.boxes = read_all<cloth::Box>(r, root, "box", read_box);
  s.scene.shapes.capsules = read_all<cloth::Capsule>(r, root, "capsule", read_capsule);
  s.scene.shapes.cylinders = read_all<cloth::Cylinder>(r, root, "cylinder", read_cylinder);
}

/// Every [[engine]], with unique names and steps that divide the frame interval.
void read_engines(const Reader& r, const toml::table& root,
                  const std::vector<const toml::table*>& engines, Scenario& s) {
  if (engines.empty())
    r.fail(root.get("engine") ? root.get("engine") : &root, "engine",
           "expected at least one [[engine]], got none");
  std::map<std::string, int> first_with_name;
  for (size_t k = 0; k < engines.size(); ++k) {
    const toml::table& t = *engines[k];
    EngineSpec e = read_engine(r, t, static_cast<int>(k));
    if (e.kind == EngineKind::external) resolve_external_command(e.external, s.source);
    const std::string path = "engine." + e.name;
    if (const auto [it, added] = first_with_name.emplace(e.name, static_cast<int>(k)); !added)
      r.fail(t.get("name") ? t.get("name") : &t, "engine." + std::to_string(k) + ".name",
             "expected a name no other engine has, got " + toml_string(e.name) + ", which engine " +
                 std::to_string(it->second) + " has too" +
                 (t.get("name") ? "" : " (derived from kind and integrator: name each engine)"));
    if (!whole_multiple(s.frame_interval, e.dt)) {
      const auto [n, key] = blame({{t.get("dt") ? t.get("dt") : &t, path + ".dt"},
                                   {root.get("frame_interval"), "frame_interval"}});
      r.fail(n, key,
             "expected frame_interval to be a whole multiple of dt, got frame_interval = " +
                 toml_double(s.frame_interval) + " s and dt = " + toml_double(e.dt) + " s");
    }
    if (s.duration / e.dt > kMaxSteps)
      r.fail(t.get("dt") ? t.get("dt") : &t, path + ".dt",
             "expected a dt that takes at most " + cloth::shortest_decimal(kMaxSteps) +
                 " steps over duration = " + toml_double(s.duration) +
                 " s, got dt = " + toml_double(e.dt) + " s (" +
                 cloth::shortest_decimal(s.duration / e.dt) + " steps)");
    s.engines.push_back(std::move(e));
  }
}

/// The reference engine, by name; the first one unless given.
void read_reference(const Reader& r, const toml::table& root, Scenario& s) {
  s.reference = s.engines.front().name;
  if (const toml::node* n = root.get("reference")) {
    s.reference = r.string({root, ""}, "reference", "");
    Keys names;
    for (const EngineSpec& e : s.engines) names.push_back(e.name);
    if (!contains(names, s.reference))
      r.fail(n, "reference",
             "expected the name of an engine, got " + toml_string(s.reference) +
                 suggest(s.reference, names));
  }
}

/// The node of the dotted scene key (as a refusal names it: "sphere.0.margin") in root.
const toml::node* scene_node(const toml::table& root, const std::string& key) {
  toml::node_view<const toml::node> view{root};
  for (size_t b = 0;;) {
    const size_t e = key.find('.', b);
    const std::string part = key.substr(b, e - b);
    const bool index = !part.empty() && std::all_of(part.begin(), part.end(), ::isdigit);
    view = index ? view[std::stoul(part)] : view[part];
    if (e == std::string::npos) break;
    b = e + 1;
  }
  return view.node();
}

/// Refuses, at the place to blame, an engine that cannot model the scene: a key a --set
/// override changed among the ones the refusal names, else the engine's kind.
void refuse_unmodelled(const Reader& r, const toml::table& root, const toml::table& t,
                       const EngineSpec& e, const cloth::Scene& scene) {
  const auto refusal = engine_refusal(e, scene);
  if (!refusal) return;
  const std::string path = "engine." + e.name;
  for (const std::string& key : refusal->scene_keys)
    if (const toml::node* n = scene_node(root, key); from_override(n)) r.fail(n, key, refusal->why);
  for (const std::string& key : refusal->engine_keys)
    if (const toml::node* n = t.get(key); from_override(n))
      r.fail(n, path + "." + key, refusal->why);
  r.fail(t.get("kind") ? t.get("kind") : &t, path, refusal->why);
}

/// Keeps the engines named in only (all when empty) and the reference; only they must be able
/// to model the scene.
void keep_engines(const Reader& r, const toml::table& root,
                  const std::vector<const toml::table*>& engines,
                  const std::vector<std::string>& only, Scenario& s) {
  Keys names;
  for (const EngineSpec& e : s.engines) names.push_back(e.name);
  for (const std::string& name : only)
    if (!contains(names, name))
      throw ScenarioError(s.source, "engine",
                          "expected the name of one of the scenario's engines, got " +
                              toml_string(name) + suggest(name, names));
  std::vector<EngineSpec> kept;
  for (size_t k = 0; k < s.engines.size(); ++k) {
    EngineSpec& e = s.engines[k];
    if (!only.empty() && e.name != s.reference &&
        std::find(only.begin(), only.end(), e.name) == only.end())
      continue;
    refuse_unmodelled(r, root, *engines[k], e, engine_scene(s, e));
    kept.push_back(std::move(e));
  }
  s.engines = std::move(kept);
}

/// A particle as the scenario names it: a grid's (i, j), a mesh's 0-based vertex index.
std::string particle_name(const cloth::Scene& scene, int p) {
  if (scene.mesh) return std::to_string(p);
  return "(" + std::to_string(p % scene.cloth.nu) + ", " + std::to_string(p / scene.cloth.nu) + ")";
}

/// The two elements of a pair as the scenario names them.
std::string pair_name(const cloth::Scene& scene, const cloth::ProximityPair& pair) {
  const auto n = [&](int k) { return particle_name(scene, pair.vertices[size_t(k)]); };
  const std::string kind = scene.mesh ? "vertex " : "particle ";
  if (pair.kind == cloth::PairKind::kVertexTriangle)
    return kind + n(0) + " and the triangle " + n(1) + ", " + n(2) + ", " + n(3);
  return "the edge " + n(0) + " - " + n(1) + " and the edge " + n(2) + " - " + n(3);
}

/// Refuses a thickness the rest shape already violates, when an engine keeps layers apart:
/// elements more than two rings apart closer than the thickness at rest.
void refuse_thin_rest_shape(const Reader& r, const toml::table& root, const Scenario& s) {
  const bool any = std::any_of(s.engines.begin(), s.engines.end(), [&](const EngineSpec& e) {
    return self_collision_of(e, s.scene.cloth) == SelfCollision::on;
  });
  if (!any) return;
  const cloth::Matrix3X x0 = cloth::rest_positions(s.scene);
  const auto& tris = s.scene.mesh ? s.scene.mesh->triangles
                                  : cloth::grid_triangles(s.scene.cloth.nu, s.scene.cloth.nv);
  cloth::SelfContactParams p;
  p.thickness = s.scene.cloth.thickness;
  const auto pair = cloth::SelfContact(static_cast<int>(x0.cols()), tris, p).closest_violation(x0);
  if (!pair) return;
  const std::string apart = cloth::significant(pair->distance, 3);
  const toml::node* n = scene_node(root, "cloth.thickness");
  if (!n) n = scene_node(root, "cloth");
  r.fail(n ? n : &root, "cloth.thickness",
         "self-contact keeps layers " + toml_double(p.thickness) + " m apart, but at rest " +
             pair_name(s.scene, *pair) + " are already " + apart +
             " m apart (more than two rings apart): give a thickness below that, or a mesh "
             "whose edges are longer than about twice the thickness");
}

/// A warning for each engine that runs without the self-collision the cloth asks for.
void note_self_collision_unavailable(Scenario& s) {
  for (const EngineSpec& e : s.engines)
    if (s.scene.cloth.self_collision && !e.self_collision &&
        self_collision_of(e, s.scene.cloth) == SelfCollision::not_available)
      s.warnings.push_back("engine " + e.name +
                           ": cloth.self_collision = true is not available in " +
                           engine_kind_name(e.kind) +
                           "; it runs without (run.json says so) and its crossings are counted");
}

Scenario read_scenario(const toml::table& root, const std::string& source,
                       const std::vector<std::string>& only) {
  const Reader r(source);
  r.check_keys({root, ""}, kTopKeys);
  Scenario s;
  s.source = source;
  read_header(r, root, s);
  read_scene(r, root, s);
  read_test(r, root, s);
  const auto engines = r.tables({root, ""}, "engine");
  read_engines(r, root, engines, s);
  read_reference(r, root, s);
  // an engine's own scene: this same reading, of the root its overrides give
  read_engine_overrides(r, root, engines, s,
                        [&](const toml::table& own) { return read_scenario(own, source, {}); });
  keep_engines(r, root, engines, only, s);
  refuse_thin_rest_shape(r, root, s);
  note_self_collision_unavailable(s);
  return s;
}

}  // namespace

Scenario parse_scenario(std::string_view toml_text, const std::string& source_name,
                        const std::vector<std::string>& overrides,
                        const std::vector<std::string>& only) {
  // a structurally extreme file would exhaust the parser's stack before it could complain
  if (const auto problem = toml_structure_problem(toml_text))
    throw ScenarioError(source_name + ":" + std::to_string(problem->first), "",
                        "not a scenario file: " + problem->second);
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    const auto line = std::max<toml::source_index>(e.source().begin.line, 1);
    throw ScenarioError(source_name + ":" + std::to_string(line), "",
                        "TOML syntax error (column " + std::to_string(e.source().begin.column) +
                            "): " + std::string(e.description()));
  }
  for (const std::string& o : overrides) apply_override(root, o);
  try {
    return read_scenario(root, source_name, only);
  } catch (const ScenarioError& e) {
    // a line of the file may be wrong only because of an override: say which were applied
    if (overrides.empty() || e.where().rfind(source_name + ":", 0) != 0 ||
        e.problem().find("--set ") != std::string::npos)
      throw;
    std::string applied;
    for (const std::string& o : overrides) applied += (applied.empty() ? "" : " ") + ("--set " + o);
    throw ScenarioError(e.where(), e.key(), e.problem() + " (with " + applied + " applied)");
  }
}

Scenario load_scenario(const std::string& path, const std::vector<std::string>& overrides,
                       const std::vector<std::string>& only) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw ScenarioError(path, "", "expected a scenario file, got a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ScenarioError(path, "",
                        std::string("cannot open the scenario file: ") + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ScenarioError(path, "", "cannot read the scenario file");
  return parse_scenario(text.str(), path, overrides, only);
}

std::string embedded_default_scenario() {
  return std::string(reinterpret_cast<const char*>(generated::kSeedScenario),
                     sizeof generated::kSeedScenario);
}

}  // namespace clothbench
