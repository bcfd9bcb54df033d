#include "harness/scenario/test_reader.hpp"

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
  if (t.get("edge"))
    r.fail(t.get("edge"), "test.edge",
           "expected no edge with a drape test (edge is the cantilever's)");
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

}  // namespace

void read_test(const Reader& r, const toml::table& root, Scenario& s) {
  const toml::table* t = r.table({root, ""}, "test");
  if (!t) return;
  const At at{*t, "test"};
  r.check_keys(at, kTestKeys);
  if (!t->get("kind")) r.fail(t, "test.kind", "expected a kind, got none");
  s.test.kind = r.choice(at, "kind", "", kTestKinds);
  if (s.test.kind == "drape") return check_drape(r, *t, root, s);
  if (s.test.kind != "cantilever")
    r.fail(t->get("kind"), "test.kind",
           "the " + toml_string(s.test.kind) +
               " test is not yet measured by the harness (\"cantilever\" and \"drape\" are)");
  s.test.edge = r.number(at, "edge", s.test.edge, kAnyNumber);
  check_cantilever(r, *t, root, s);
}

}  // namespace clothbench
