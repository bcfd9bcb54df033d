#include "harness/scenario/selection_reader.hpp"

#include <algorithm>
#include <limits>

#include "cloth/model/triangle_mesh.hpp"

namespace clothbench {

namespace {

/// The keys each selection owns; a key given to another selection is an error.
struct KeyOwner {
  const char* key;
  Keys owners;
};
const KeyOwner kOwners[] = {{"center", {"disk", "within"}},
                            {"radius", {"disk", "within"}},
                            {"list", {"indices"}},
                            {"name", {"group"}},
                            {"min", {"box"}},
                            {"max", {"box"}}};

/// "a" or "a" or "b", quoted.
std::string either(const Keys& k) {
  std::string s;
  for (size_t i = 0; i < k.size(); ++i) s += (i ? " or \"" : "\"") + std::string(k[i]) + "\"";
  return s;
}

/// A disk in the cloth plane: center = [a, b] on the plane's axes and radius.
void read_disk(const Reader& r, const At& at, const cloth::Scene& scene, ConstraintSpec& c) {
  const char* axes = scene.cloth.plane == cloth::Plane::xz ? "x, z" : "x, y";
  if (!at.table.get("center"))
    r.fail(&at.table, at.key("center"),
           std::string("a disk needs center = [a, b] (m, on the cloth plane's ") + axes + " axes)");
  if (!at.table.get("radius")) r.fail(&at.table, at.key("radius"), "a disk needs radius = r (m)");
  const auto center = r.number_pair(at, "center", {0, 0}, kAnyNumber);
  c.disk_center_x = center[0];
  c.disk_center_z = center[1];
  c.disk_radius = r.number(at, "radius", 0.0, kLength);
}

/// A ball (center = [x, y, z], radius) or a box (min, max) around rest positions.
void read_region(const Reader& r, const At& at, ConstraintSpec& c) {
  const bool ball = c.select == "within";
  for (const char* key :
       ball ? std::vector<const char*>{"center", "radius"} : std::vector<const char*>{"min", "max"})
    if (!at.table.get(key))
      r.fail(&at.table, at.key(key),
             ball ? "select = \"within\" needs center = [x, y, z] and radius = r (m)"
                  : "select = \"box\" needs min = [x, y, z] and max = [x, y, z] (m)");
  if (ball) {
    c.center = r.vec3(at, "center", c.center);
    c.disk_radius = r.number(at, "radius", 0.0, kLength);
    return;
  }
  c.box_min = r.vec3(at, "min", c.box_min);
  c.box_max = r.vec3(at, "max", c.box_max);
  for (int a = 0; a < 3; ++a)
    if (!(c.box_min[a] <= c.box_max[a]))
      r.fail(at.table.get("max"), at.key("max"),
             "expected max >= min on every axis, got max below min on " + std::string(1, "xyz"[a]));
}

/// indices: [[i, j], ...] on a grid, [v, ...] (0-based vertex indices) on a mesh.
void read_indices(const Reader& r, const At& at, const cloth::Scene& scene, ConstraintSpec& c) {
  const toml::node* n = at.table.get("list");
  const bool mesh = scene.mesh != nullptr;
  if (!n)
    r.fail(&at.table, at.key("list"),
           mesh ? "select = \"indices\" needs list = [v, ...] (0-based vertex indices)"
                : "select = \"indices\" needs list = [[i, j], ...]");
  const toml::array* list = n->as_array();
  if (!list || list->empty())
    r.expected(
        *n, at.key("list"),
        mesh ? "a non-empty array of vertex indices" : "a non-empty array of [i, j] grid indices");
  const cloth::ClothParams& cloth = scene.cloth;
  const int count = scene.particle_count();
  for (size_t k = 0; k < list->size(); ++k) {
    const toml::node& e = *list->get(k);
    const std::string key = at.key("list") + "." + std::to_string(k);
    if (mesh) {
      const auto* v = e.as_integer();
      if (!v || v->get() < 0 || v->get() >= count)
        r.fail(&e, key,
               "expected a vertex index from 0 to " + std::to_string(count - 1) +
                   " (the mesh has " + std::to_string(count) + " vertices), got " + describe(e));
      c.vertices.push_back(static_cast<int>(v->get()));
      continue;
    }
    const auto ij = Reader::int_pair(e, std::numeric_limits<int>::min());
    if (!ij) r.expected(e, key, "an [i, j] pair of integers");
    const auto [i, j] = *ij;
    if (i < 0 || i >= cloth.nu || j < 0 || j >= cloth.nv)
      r.fail(&e, key,
             "expected a grid index with i in 0.." + std::to_string(cloth.nu - 1) +
                 " and j in 0.." + std::to_string(cloth.nv - 1) + " (the grid has " +
                 std::to_string(cloth.nu) + " x " + std::to_string(cloth.nv) + " particles), got " +
                 describe(e));
    c.indices.emplace_back(i, j);
  }
}

/// group: a named vertex group of the mesh.
void read_group(const Reader& r, const At& at, const cloth::Scene& scene, ConstraintSpec& c) {
  if (!at.table.get("name"))
    r.fail(&at.table, at.key("name"), "select = \"group\" needs name = \"...\"");
  c.group = r.string(at, "name", "");
  Keys names;
  for (const auto& g : scene.mesh->groups) names.push_back(g.first);
  if (!contains(names, c.group))
    r.fail(at.table.get("name"), at.key("name"),
           "expected a group of the mesh (" +
               (names.empty() ? std::string("it has none") : join(names, "\"")) + "), got " +
               toml_string(c.group) + suggest(c.group, names));
}

/// The error of a region that holds no particle, blamed on its size.
[[noreturn]] void fail_empty(const Reader& r, const At& at, const cloth::Scene& scene,
                             const ConstraintSpec& c) {
  if (c.select == "disk") {
    const char* axes = scene.cloth.plane == cloth::Plane::xz ? "x, z" : "x, y";
    r.fail(at.table.get("radius"), at.key("radius"),
           "expected a disk that covers at least one particle, got radius " +
               toml_double(c.disk_radius) + " m around [" + toml_double(c.disk_center_x) + ", " +
               toml_double(c.disk_center_z) + "] (" + axes + "), which holds none");
  }
  if (c.select == "within")
    r.fail(at.table.get("radius"), at.key("radius"),
           "expected a ball that holds at least one particle's rest position, got radius " +
               toml_double(c.disk_radius) + " m, which holds none");
  if (c.select == "group")
    r.fail(at.table.get("name"), at.key("name"),
           "expected a group with vertices, got " + toml_string(c.group) + ", which has none");
  r.fail(at.table.get("max"), at.key("max"),
         "expected a box that holds at least one particle's rest position, got none inside");
}

}  // namespace

ConstraintSpec read_selection(const Reader& r, const toml::table& t, const std::string& path,
                              const cloth::Scene& scene, const Keys& keys) {
  const At at{t, path};
  r.check_keys(at, keys);
  ConstraintSpec c;
  c.select = r.choice(at, "select", scene.mesh ? "group" : c.select, kSelections);
  const bool mesh = scene.mesh != nullptr;
  const Keys grid_only = {"corners", "edge:u0", "edge:u1", "edge:v0", "edge:v1", "disk"};
  if (mesh && contains(grid_only, c.select))
    r.fail(t.get("select") ? t.get("select") : &t, at.key("select"),
           "selects on a grid; a mesh selects \"group\", \"indices\", \"within\" or \"box\"");
  if (!mesh && c.select == "group")
    r.fail(t.get("select"), at.key("select"),
           "a grid has no vertex groups; groups come from a mesh's g/o names");
  if (contains(keys, "hold")) {
    const std::string hold = r.string(at, "hold", hold_letters(c.hold));
    c.hold = parse_hold(hold);
    if (c.hold == 0)
      r.fail(
          t.get("hold"), at.key("hold"),
          "expected a non-empty combination of the letters x, y and z, got " + toml_string(hold));
  }
  // each selection takes its own keys
  for (const KeyOwner& o : kOwners)
    if (const toml::node* n = t.get(o.key); n && !contains(o.owners, c.select))
      r.fail(n, at.key(o.key),
             "applies only to select = " + either(o.owners) + ", this constraint selects " +
                 toml_string(c.select));
  if (c.select == "disk") read_disk(r, at, scene, c);
  if (c.select == "within" || c.select == "box") read_region(r, at, c);
  if (c.select == "indices") read_indices(r, at, scene, c);
  if (c.select == "group") read_group(r, at, scene, c);
  // a region that holds nothing is a mistake, said with where it looked
  const std::vector<std::uint8_t> mask = held_mask(scene, {c});
  if (std::none_of(mask.begin(), mask.end(), [](std::uint8_t m) { return m != 0; }))
    fail_empty(r, at, scene, c);
  return c;
}

}  // namespace clothbench
