#include "harness/scenario/test_reader.hpp"

#include <algorithm>
#include <cmath>

#include "cloth/model/mesh_generator.hpp"
#include "cloth/model/model.hpp"
#include "harness/scenario/scenario_format.hpp"

namespace clothbench {

namespace {

/// A particle as the scenario names it: a grid's (i, j), a mesh's 0-based vertex index.
std::string named(const cloth::Scene& scene, Eigen::Index p) {
  if (scene.mesh) return "vertex " + std::to_string(p);
  const int nu = scene.cloth.nu;
  return "particle (" + std::to_string(p % nu) + ", " + std::to_string(p / nu) + ")";
}

/// The cantilever's checks: a held platform up to the edge, an overhang beyond it, a weight.
void check_cantilever(const Reader& r, const toml::table& t, const toml::table& root,
                      const Scenario& s) {
  const cloth::Matrix3X x0 = cloth::rest_positions(s.scene);
  const toml::node* edge = t.get("edge") ? t.get("edge") : &t;
  const std::string at = toml_double(s.test.edge) + " m";
  bool on = false, over = false;
  for (Eigen::Index p = 0; p < x0.cols(); ++p) {
    if (x0(0, p) > s.test.edge) {
      over = true;
      continue;
    }
    on = true;
    // the platform: held on every axis, so the clamp is level and does not slide
    if (s.scene.held[size_t(p)] != cloth::kHoldAll)
      r.fail(edge, "test.edge",
             "expected every particle at rest x <= edge = " + at +
                 " held on x, y and z by a [[constraint]] (the platform), got " +
                 named(s.scene, p) + " at x = " + toml_double(x0(0, p)) + " m held on \"" +
                 hold_letters(s.scene.held[size_t(p)]) +
                 "\" (add e.g. [[constraint]] select = \"box\" around the strip up to the edge)");
  }
  if (!on)
    r.fail(edge, "test.edge",
           "expected particles at rest x <= edge = " + at + " (the platform), got none");
  if (!over)
    r.fail(edge, "test.edge",
           "expected particles at rest x > edge = " + at + " (the overhang), got none");
  if (s.scene.gravity.norm() == 0)
    r.fail(root.get("gravity") ? root.get("gravity") : &t, "gravity",
           "expected a non-zero gravity with a cantilever test (the strip bends under its weight)");
}

/// The drape test's checks: a held support (a disk the drape coefficient can measure) and a
/// weight.
void check_drape(const Reader& r, const toml::table& t, const toml::table& root,
                 const Scenario& s) {
  for (const char* key : {"edge", "direction", "fit_strain", "overhang_rule", "fit_angle"})
    if (t.get(key))
      r.fail(t.get(key), std::string("test.") + key,
             std::string("expected no ") + key + " with a drape test (it is another test's key)");
  bool disk = false;
  for (const ConstraintSpec& c : s.constraints)
    disk = disk || c.select == "disk" || c.select == "within";
  if (!disk)
    r.fail(t.get("kind"), "test.kind",
           "expected the specimen's support held by a [[constraint]] select = \"within\" (a mesh) "
           "or \"disk\" (a grid) with a drape test, got none");
  if (s.scene.gravity.norm() == 0)
    r.fail(root.get("gravity") ? root.get("gravity") : &t, "gravity",
           "expected a non-zero gravity with a drape test (the specimen hangs under its weight)");
}

/// The extension axis of a grid's direction "u" (x) or "v" (z, or y when plane = "xy").
cloth::Vector3 tensile_axis(const cloth::ClothParams& c, const std::string& direction) {
  if (direction == "u") return cloth::Vector3::UnitX();
  return c.plane == cloth::Plane::xy ? cloth::Vector3::UnitY() : cloth::Vector3::UnitZ();
}

/// True when the handle's motion only ever moves it forward along axis.
bool pulls_along(const cloth::Motion& m, const cloth::Vector3& axis) {
  std::vector<cloth::Vector3> d;
  if (m.path.empty()) d.push_back(m.velocity);
  for (const auto& row : m.path) d.emplace_back(row[1], row[2], row[3]);
  bool forward = false;
  for (const cloth::Vector3& v : d) {
    const double along = v.dot(axis);
    if (along < 0 || (v - along * axis).norm() > 1e-12 * v.norm()) return false;
    forward = forward || along > 0;
  }
  return forward;
}

/// The strip-tensile's checks: a grid, a clamp held on every axis, one handle beyond it that
/// pulls along the direction.
void check_strip_tensile(const Reader& r, const toml::table& t, const toml::table& root,
                         const Scenario& s) {
  const toml::node* at = t.get("direction") ? t.get("direction") : &t;
  if (s.scene.mesh)
    r.fail(t.get("kind"), "test.kind",
           "the strip-tensile test is not yet measured on a mesh: give the strip as a grid "
           "(particles, size)");
  if (s.scene.handles.size() != 1)
    r.fail(root.get("handle") ? root.get("handle") : &t, "handle",
           "expected one [[handle]] with a strip-tensile test (the moving clamp), got " +
               std::to_string(s.scene.handles.size()));
  const cloth::Vector3 axis = tensile_axis(s.scene.cloth, s.test.direction);
  if (!pulls_along(s.scene.handles[0].motion, axis))
    r.fail(root.get("handle"), "handle.path",
           "expected the strip-tensile handle to move forward along the test's direction " +
               toml_string(s.test.direction) + " alone (a velocity or path parallel to it)");
  // the clamp's last particle before the handle's first, along the axis
  const cloth::Matrix3X x0 = cloth::rest_positions(s.scene);
  double clamp = -HUGE_VAL, handle = HUGE_VAL;
  for (Eigen::Index p = 0; p < x0.cols(); ++p)
    if (size_t(p) < s.scene.held.size() && s.scene.held[size_t(p)] == cloth::kHoldAll)
      clamp = std::max(clamp, x0.col(p).dot(axis));
  for (int p : s.scene.handles[0].particles) handle = std::min(handle, x0.col(p).dot(axis));
  if (!std::isfinite(clamp) || !(clamp < handle))
    r.fail(at, "test.direction",
           "expected particles held on x, y and z by a [[constraint]] (the fixed clamp), all "
           "of them before the handle's particles along direction " +
               toml_string(s.test.direction));
}

/// The bias-extension's specimen: a generated rectangle of yarns at 45 degrees, at least
/// twice as long (u, x) as wide.
void check_bias_specimen(const Reader& r, const toml::table& t, const Scenario& s) {
  const cloth::ShapeSpec& g = s.mesh.shape;
  const bool bias = s.mesh.generated && g.shape == cloth::MeshShape::rectangle &&
                    g.lattice == cloth::MeshLattice::grid &&
                    std::lround(g.lattice_angle / 45.0) % 2 != 0;
  if (!bias)
    r.fail(t.get("kind"), "test.kind",
           "expected the bias-extension specimen as a [cloth.generate] shape = \"rectangle\" "
           "with lattice = \"grid\" and lattice_angle = 45 (yarns at +-45 degrees to its length, "
           "u)");
  if (!(g.size_u >= 2 * g.size_v))
    r.fail(t.get("kind"), "test.kind",
           "expected the bias-extension specimen at least twice as long (size u, along x) as "
           "wide (size v), got " +
               toml_double(g.size_u) + " m by " + toml_double(g.size_v) +
               " m (the central zone is in pure shear only then)");
}

/// The bias-extension's checks: its specimen, a clamp held on every axis, one handle beyond
/// it that pulls along x, a central zone to measure.
void check_bias_extension(const Reader& r, const toml::table& t, const toml::table& root,
                          const Scenario& s) {
  for (const char* key : {"edge", "direction", "fit_strain"})
    if (t.get(key))
      r.fail(t.get(key), std::string("test.") + key,
             std::string("expected no ") + key +
                 " with a bias-extension test (it is another test's key)");
  check_bias_specimen(r, t, s);
  if (s.scene.handles.size() != 1)
    r.fail(root.get("handle") ? root.get("handle") : &t, "handle",
           "expected one [[handle]] with a bias-extension test (the moving clamp), got " +
               std::to_string(s.scene.handles.size()));
  if (!pulls_along(s.scene.handles[0].motion, cloth::Vector3::UnitX()))
    r.fail(root.get("handle"), "handle.path",
           "expected the bias-extension handle to move forward along x alone (the specimen's "
           "length, u)");
  // the clamp before the handle
  const cloth::Matrix3X x0 = cloth::rest_positions(s.scene);
  double clamp = -HUGE_VAL, handle = HUGE_VAL;
  for (Eigen::Index p = 0; p < x0.cols(); ++p)
    if (size_t(p) < s.scene.held.size() && s.scene.held[size_t(p)] == cloth::kHoldAll)
      clamp = std::max(clamp, x0(0, p));
  for (int p : s.scene.handles[0].particles) handle = std::min(handle, x0(0, p));
  if (!std::isfinite(clamp) || !(clamp < handle))
    r.fail(t.get("kind"), "test.kind",
           "expected particles held on x, y and z by a [[constraint]] (the fixed clamp), all "
           "of them before the handle's particles along x");
  // the central zone the angle is measured on: within W/4 of the middle along and across
  const cloth::ShapeSpec& g = s.mesh.shape;
  const int across = g.plane == cloth::Plane::xy ? 1 : 2;
  const double mid = 0.5 * (clamp + handle), quarter = 0.25 * g.size_v * (1 + 1e-12);
  int central = 0;
  for (Eigen::Index p = 0; p < x0.cols(); ++p)
    central += std::abs(x0(0, p) - mid) <= quarter &&
               std::abs(x0(across, p) - g.center[across]) <= quarter;
  if (central < 3)
    r.fail(t.get("kind"), "test.kind",
           "expected at least 3 particles within a quarter of the width of the specimen's "
           "middle (the central zone whose shear angle is measured), got " +
               std::to_string(central) + ": a smaller edge_length");
}

}  // namespace

void read_test(const Reader& r, const toml::table& root, Scenario& s) {
  const toml::table* t = r.table({root, ""}, "test");
  if (!t) return;
  const At at{*t, "test"};
  r.check_keys(at, kTestKeys);
  if (!t->get("kind")) r.fail(t, "test.kind", "expected a kind, got none");
  s.test.kind = r.choice(at, "kind", "", kTestKinds);
  if (s.test.kind == "drape") return check_drape(r, *t, root, s);
  s.test.fit_angle = r.number(at, "fit_angle", s.test.fit_angle, kPositive);
  if (s.test.kind == "bias-extension") return check_bias_extension(r, *t, root, s);
  if (t->get("fit_angle"))
    r.fail(t->get("fit_angle"), "test.fit_angle",
           "expected no fit_angle with a " + toml_string(s.test.kind) +
               " test (it is the bias-extension's key)");
  s.test.edge = r.number(at, "edge", s.test.edge, kAnyNumber);
  s.test.direction = r.choice(at, "direction", s.test.direction, kTensileDirections);
  s.test.fit_strain = r.number(at, "fit_strain", s.test.fit_strain, kPositive);
  s.test.overhang_rule = r.choice(at, "overhang_rule", s.test.overhang_rule, kOverhangRules);
  if (s.test.kind != "cantilever" && t->get("overhang_rule"))
    r.fail(t->get("overhang_rule"), "test.overhang_rule",
           "expected no overhang_rule with a " + s.test.kind + " test (it is the cantilever's)");
  if (s.test.kind == "cantilever")
    check_cantilever(r, *t, root, s);
  else
    check_strip_tensile(r, *t, root, s);
}

}  // namespace clothbench
