#include "harness/scenario_loader.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "harness/embedded_seed_scenario.hpp"
#include "harness/engine_factory.hpp"

namespace clothbench {

ScenarioError::ScenarioError(const std::string& where, const std::string& key,
                             const std::string& problem)
    : UserError(where + ": " + (key.empty() ? "" : key + ": ") + problem),
      m_where(where),
      m_key(key),
      m_problem(problem) {}

namespace {

using Keys = std::vector<std::string_view>;

// the keys of each table of the file format
const Keys kTopKeys = {
    "name",          "description", "duration", "frame_interval", "snapshot_interval",
    "blowup_strain", "reference",   "gravity",  "cloth",          "constraint",
    "sphere",        "engine"};
const Keys kClothKeys = {"particles",  "size",      "center",  "plane",   "particle_mass",
                         "total_mass", "stiffness", "damping", "air_drag"};
const Keys kStiffnessKeys = {"structural", "shear", "bend"};
const Keys kConstraintKeys = {"select", "hold", "center", "radius", "list"};
const Keys kSphereKeys = {"center", "radius", "restitution", "friction", "velocity", "margin"};
const Keys kEngineCommonKeys = {"name", "kind", "dt"};
const Keys kCustomKeys = {"integrator", "newton_iterations", "cg_tolerance", "cg_max_iterations",
                          "clamp_compressed"};
const Keys kDeformableKeys = {"implicit", "line_search", "projection"};
const Keys kSoftbodyKeys = {"stiffness", "klst", "iterations"};

// the values of the enumerated keys
const Keys kEngineKinds = {"custom", "bullet-deformable", "bullet-softbody"};
const Keys kPlanes = {"xz", "xy"};
const Keys kSelections = {"corners", "edge:u0", "edge:u1", "edge:v0", "edge:v1", "disk", "indices"};
const Keys kSoftbodyStiffness = {"matched", "klst"};

/// The kind-specific keys of an engine kind.
const Keys& engine_kind_keys(std::string_view kind) {
  if (kind == "bullet-deformable") return kDeformableKeys;
  if (kind == "bullet-softbody") return kSoftbodyKeys;
  return kCustomKeys;
}

Keys all_engine_keys() {
  Keys k = kEngineCommonKeys;
  for (const Keys* kind : {&kCustomKeys, &kDeformableKeys, &kSoftbodyKeys})
    k.insert(k.end(), kind->begin(), kind->end());
  return k;
}

Keys integrator_names() {
  Keys k;
  for (cloth::Integrator i : cloth::all_integrators()) k.push_back(cloth::integrator_name(i));
  return k;
}

bool contains(const Keys& keys, std::string_view k) {
  return std::find(keys.begin(), keys.end(), k) != keys.end();
}

// ---- text

/// Shortest decimal that reads back as exactly x: plain for everyday magnitudes ("0.0003",
/// "20000", "-3"), scientific for the very small and very large ("1e-08").
std::string shortest(double x) {
  char buf[512];
  const double a = std::abs(x);
  const auto format =
      a == 0 || (a >= 1e-5 && a < 1e16) ? std::chars_format::fixed : std::chars_format::scientific;
  const auto r = std::to_chars(buf, buf + sizeof buf, x, format);
  return std::string(buf, r.ptr);
}

/// x as a TOML float: shortest form, with ".0" where it would otherwise read as an integer.
std::string toml_double(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::string s = shortest(x);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

/// s as a TOML basic string, quoted and escaped.
std::string toml_string(std::string_view s) {
  std::string out = "\"";
  for (char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (ch) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char esc[8];
          std::snprintf(esc, sizeof esc, "\\u%04x", c);
          out += esc;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

std::string join(const Keys& keys, const char* quote = "") {
  std::string out;
  for (std::string_view k : keys) {
    if (!out.empty()) out += ", ";
    out += quote;
    out += k;
    out += quote;
  }
  return out;
}

/// A value as the user wrote it, for "got ..." in messages.
std::string describe(const toml::node& n) {
  if (const auto* s = n.as_string()) return toml_string(s->get());
  if (const auto* i = n.as_integer()) return std::to_string(i->get());
  if (const auto* f = n.as_floating_point()) return toml_double(f->get());
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* a = n.as_array()) {
    std::string out = "[";
    for (size_t k = 0; k < a->size(); ++k) {
      if (k == 6) {
        out += ", ...";
        break;
      }
      out += (k ? ", " : "") + describe(*a->get(k));
    }
    return out + "]";
  }
  if (n.is_table()) return "a table";
  return "a date or time";
}

size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      const size_t substitute = diagonal + (std::tolower(a[i - 1]) != std::tolower(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
      diagonal = up;
    }
  }
  return row[b.size()];
}

/// "; did you mean "x"?" when word is a near miss of one of known, else "".
std::string near_miss(std::string_view word, const Keys& known) {
  std::string_view best;
  size_t best_distance = std::string_view::npos;
  for (std::string_view k : known) {
    size_t d = edit_distance(word, k);
    // a word that is the start of a longer name is one edit away in spirit
    if (word.size() >= 3 && (k.substr(0, word.size()) == word || word.substr(0, k.size()) == k))
      d = std::min<size_t>(d, 1);
    if (d < best_distance) best = k, best_distance = d;
  }
  const size_t allowed = std::max<size_t>(1, std::min<size_t>(3, (word.size() + 1) / 3));
  if (!best.empty() && best_distance <= allowed)
    return "; did you mean \"" + std::string(best) + "\"?";
  return "";
}

/// "; did you mean "x"?" for a near miss, else " (expected one of: ...)".
std::string suggest(std::string_view word, const Keys& known) {
  const std::string near = near_miss(word, known);
  return near.empty() ? " (expected one of: " + join(known) + ")" : near;
}

bool whole_multiple(double big, double small) {
  const double r = big / small;
  const double n = std::round(r);
  return n >= 1 && std::abs(r - n) <= 1e-9 * r;
}

std::string hold_letters(std::uint8_t hold) {
  std::string s;
  if (hold & cloth::kHoldX) s += 'x';
  if (hold & cloth::kHoldY) s += 'y';
  if (hold & cloth::kHoldZ) s += 'z';
  return s;
}

/// The axis bits of "xyz", "yz", ...; 0 for anything else (empty, repeated or other letters).
std::uint8_t parse_hold(std::string_view s) {
  std::uint8_t bits = 0;
  for (char c : s) {
    const std::uint8_t bit = c == 'x'   ? cloth::kHoldX
                             : c == 'y' ? cloth::kHoldY
                             : c == 'z' ? cloth::kHoldZ
                                        : 0;
    if (bit == 0 || (bits & bit)) return 0;
    bits |= bit;
  }
  return bits;
}

/// Engine names label CSV rows and --set keys: no dots, commas or spaces.
bool valid_engine_name(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '+';
  });
}

/// Scenario names become output folder names.
bool valid_scenario_name(std::string_view s) {
  return !s.empty() && s.front() != '.' && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
  });
}

/// The name of an engine that has none: "custom-<integrator>" or its kind.
std::string derived_engine_name(const std::string& kind, const std::string& integrator) {
  return kind == "custom" ? "custom-" + integrator : kind;
}

/// The name an [[engine]] table goes by (given or derived), for --set addressing.
std::string engine_table_name(const toml::table& t) {
  if (auto name = t["name"].value<std::string>()) return *name;
  return derived_engine_name(t["kind"].value_or(std::string("custom")),
                             t["integrator"].value_or(std::string("rk4")));
}

constexpr const char* kOverridePrefix = "--set ";

bool from_override(const toml::node* n) {
  return n && n->source().path && n->source().path->rfind(kOverridePrefix, 0) == 0;
}

std::string path_of(const std::string& prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : prefix + "." + std::string(key);
}

// ---- reading a toml::table into a Scenario, with located errors

/// A range a number must lie in, as said in messages ("> 0").
struct Bound {
  const char* text;  // "" for any finite number
  bool (*ok)(double);
};
const Bound kAnyNumber{"", [](double) { return true; }};
const Bound kPositive{"> 0", [](double x) { return x > 0; }};
const Bound kNonNegative{">= 0", [](double x) { return x >= 0; }};
const Bound kUnitInterval{"in [0, 1]", [](double x) { return x >= 0 && x <= 1; }};

std::string expected_number(const Bound& b) {
  return *b.text ? std::string("a number ") + b.text : std::string("a finite number");
}

/// A location in the key tree: a table and its dotted path ("cloth", "engine.custom-rk4").
struct At {
  const toml::table& table;
  std::string path;
  std::string key(std::string_view k) const { return path_of(path, k); }
};

class Reader {
 public:
  explicit Reader(std::string source) : m_source(std::move(source)) {}

  /// "file:line" of n, or "--set key" when an override put n there.
  std::string where(const toml::node* n) const {
    if (from_override(n)) return *n->source().path;
    const std::string file = n && n->source().path ? *n->source().path : m_source;
    const auto line = n ? std::max<toml::source_index>(n->source().begin.line, 1) : 1;
    return file + ":" + std::to_string(line);
  }

  [[noreturn]] void fail(const toml::node* n, const std::string& key,
                         const std::string& problem) const {
    const std::string w = where(n);
    throw ScenarioError(w, w == kOverridePrefix + key ? "" : key, problem);
  }

  [[noreturn]] void expected(const toml::node& n, const std::string& key,
                             const std::string& what) const {
    fail(&n, key, "expected " + what + ", got " + describe(n));
  }

  /// Rejects any key of t not in known, with a did-you-mean.
  void check_keys(const At& at, const Keys& known) const {
    for (const auto& [k, v] : at.table)
      if (!contains(known, k.str()))
        fail(&v, at.key(k.str()), "unknown key" + suggest(k.str(), known));
  }

  double number(const At& at, std::string_view key, double def, const Bound& b) const {
    const toml::node* n = at.table.get(key);
    if (!n) return def;
    const std::optional<double> x = as_number(*n);
    if (!x || !std::isfinite(*x) || !b.ok(*x)) expected(*n, at.key(key), expected_number(b));
    return *x;
  }

  int integer(const At& at, std::string_view key, int def, int min) const {
    const toml::node* n = at.table.get(key);
    if (!n) return def;
    const std::optional<int> i = as_int(*n, min);
    if (!i) expected(*n, at.key(key), "an integer >= " + std::to_string(min));
    return *i;
  }

  bool boolean(const At& at, std::string_view key, bool def) const {
    const toml::node* n = at.table.get(key);
    if (!n) return def;
    if (!n->is_boolean()) expected(*n, at.key(key), "true or false");
    return n->as_boolean()->get();
  }

  std::string string(const At& at, std::string_view key, const std::string& def) const {
    const toml::node* n = at.table.get(key);
    if (!n) return def;
    if (!n->is_string()) expected(*n, at.key(key), "a string");
    return n->as_string()->get();
  }

  /// A string that must be one of options.
  std::string choice(const At& at, std::string_view key, const std::string& def,
                     const Keys& options) const {
    const std::string s = string(at, key, def);
    if (!contains(options, s))
      fail(at.table.get(key), at.key(key),
           "expected one of " + join(options, "\"") + ", got " + toml_string(s) +
               near_miss(s, options));
    return s;
  }

  cloth::Vector3 vec3(const At& at, std::string_view key, const cloth::Vector3& def) const {
    const toml::node* n = at.table.get(key);
    if (!n) return def;
    const auto v = numbers(*n, 3, kAnyNumber);
    if (!v) expected(*n, at.key(key), "an array of 3 numbers");
    return {(*v)[0], (*v)[1], (*v)[2]};
  }

  std::array<double, 2> number_pair(const At& at, std::string_view key, std::array<double, 2> def,
                                    const Bound& b) const {
    const toml::node* n = at.table.get(key);
    if (!n) return def;
    const auto v = numbers(*n, 2, b);
    if (!v)
      expected(*n, at.key(key), "an array of 2 numbers" + std::string(*b.text ? " " : "") + b.text);
    return {(*v)[0], (*v)[1]};
  }

  /// [a, b] of integers >= min; nullopt when n is not one.
  static std::optional<std::array<int, 2>> int_pair(const toml::node& n, int min) {
    const toml::array* a = n.as_array();
    if (!a || a->size() != 2) return std::nullopt;
    const auto x = as_int(*a->get(0), min), y = as_int(*a->get(1), min);
    if (!x || !y) return std::nullopt;
    return std::array<int, 2>{*x, *y};
  }

  /// The table at key, nullptr when absent.
  const toml::table* table(const At& at, std::string_view key) const {
    const toml::node* n = at.table.get(key);
    if (n && !n->is_table()) expected(*n, at.key(key), "a table");
    return n ? n->as_table() : nullptr;
  }

  /// The [[key]] array of tables, empty when absent.
  std::vector<const toml::table*> tables(const At& at, std::string_view key) const {
    std::vector<const toml::table*> out;
    const toml::node* n = at.table.get(key);
    if (!n) return out;
    const toml::array* a = n->as_array();
    if (!a) expected(*n, at.key(key), "an array of tables ([[" + std::string(key) + "]])");
    for (size_t k = 0; k < a->size(); ++k) {
      if (!a->get(k)->is_table())
        expected(*a->get(k), at.key(key) + "." + std::to_string(k),
                 "a table ([[" + std::string(key) + "]])");
      out.push_back(a->get(k)->as_table());
    }
    return out;
  }

 private:
  static std::optional<double> as_number(const toml::node& n) {
    if (const auto* f = n.as_floating_point()) return f->get();
    if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
    return std::nullopt;
  }

  static std::optional<int> as_int(const toml::node& n, int min) {
    const auto* i = n.as_integer();
    if (!i || i->get() < min || i->get() > std::numeric_limits<int>::max()) return std::nullopt;
    return static_cast<int>(i->get());
  }

  static std::optional<std::vector<double>> numbers(const toml::node& n, size_t count,
                                                    const Bound& b) {
    const toml::array* a = n.as_array();
    if (!a || a->size() != count) return std::nullopt;
    std::vector<double> v;
    for (const toml::node& e : *a) {
      const auto x = as_number(e);
      if (!x || !std::isfinite(*x) || !b.ok(*x)) return std::nullopt;
      v.push_back(*x);
    }
    return v;
  }

  std::string m_source;
};

/// Of several places an error could be reported, the one a --set override put there, else the
/// first that exists.
std::pair<const toml::node*, std::string> blame(
    std::initializer_list<std::pair<const toml::node*, std::string>> places) {
  for (const auto& p : places)
    if (from_override(p.first)) return p;
  for (const auto& p : places)
    if (p.first) return p;
  return *places.begin();
}

cloth::ClothParams read_cloth(const Reader& r, const toml::table* table) {
  cloth::ClothParams c;
  if (!table) return c;
  const At at{*table, "cloth"};
  r.check_keys(at, kClothKeys);

  // grid
  if (const toml::node* n = table->get("particles")) {
    const auto p = Reader::int_pair(*n, 1);
    if (!p) r.expected(*n, "cloth.particles", "an array of 2 integers >= 1");
    const long long total = static_cast<long long>((*p)[0]) * (*p)[1];
    if (total < 2) r.expected(*n, "cloth.particles", "at least 2 particles in all");
    if (total > 10'000'000) r.expected(*n, "cloth.particles", "at most 10000000 particles in all");
    c.nu = (*p)[0];
    c.nv = (*p)[1];
  }
  const auto size = r.number_pair(at, "size", {c.size_u, c.size_v}, kNonNegative);
  for (int d = 0; d < 2; ++d) {
    // springs along a direction with several particles need a length to rest at
    const int count = d == 0 ? c.nu : c.nv;
    if (count > 1 && !(size[d] > 0))
      r.fail(table->get("size"), "cloth.size",
             std::string("expected a size > 0 along ") + (d == 0 ? "u" : "v") + ", which has " +
                 std::to_string(count) + " particles, got " + toml_double(size[d]));
  }
  c.size_u = size[0];
  c.size_v = size[1];
  c.center = r.vec3(at, "center", c.center);
  c.plane = r.choice(at, "plane", "xz", kPlanes) == "xz" ? cloth::Plane::xz : cloth::Plane::xy;

  // mass: one of the two ways of giving it
  const toml::node* pm = table->get("particle_mass");
  const toml::node* tm = table->get("total_mass");
  if (pm && tm) {
    const auto [n, key] = blame({{tm, "cloth.total_mass"}, {pm, "cloth.particle_mass"}});
    r.fail(n, key, "expected particle_mass or total_mass, got both (give the mass one way only)");
  }
  c.particle_mass = r.number(at, "particle_mass", c.particle_mass, kPositive);
  c.total_mass = r.number(at, "total_mass", c.total_mass, kPositive);

  // a stiffness table names the spring kinds there are; an omitted kind has no springs
  if (const toml::table* st = r.table(at, "stiffness")) {
    const At sat{*st, "cloth.stiffness"};
    r.check_keys(sat, kStiffnessKeys);
    c.k_structural = r.number(sat, "structural", 0.0, kNonNegative);
    c.k_shear = r.number(sat, "shear", 0.0, kNonNegative);
    c.k_bend = r.number(sat, "bend", 0.0, kNonNegative);
  }
  c.damping = r.number(at, "damping", c.damping, kNonNegative);
  c.air_drag = r.number(at, "air_drag", c.air_drag, kNonNegative);
  return c;
}

ConstraintSpec read_constraint(const Reader& r, const toml::table& t, const std::string& path,
                               const cloth::ClothParams& cloth) {
  const At at{t, path};
  r.check_keys(at, kConstraintKeys);
  ConstraintSpec c;
  c.select = r.choice(at, "select", c.select, kSelections);
  const std::string hold = r.string(at, "hold", hold_letters(c.hold));
  c.hold = parse_hold(hold);
  if (c.hold == 0)
    r.fail(t.get("hold"), at.key("hold"),
           "expected a non-empty combination of the letters x, y and z, got " + toml_string(hold));

  // each selection takes its own keys
  using KeyOwner = std::pair<const char*, const char*>;
  for (const auto& [key, owner] :
       {KeyOwner{"center", "disk"}, KeyOwner{"radius", "disk"}, KeyOwner{"list", "indices"}})
    if (const toml::node* n = t.get(key); n && c.select != owner)
      r.fail(n, at.key(key),
             std::string("applies only to select = \"") + owner + "\", this constraint selects " +
                 toml_string(c.select));

  if (c.select == "disk") {
    const char* axes = cloth.plane == cloth::Plane::xz ? "x, z" : "x, y";
    if (!t.get("center"))
      r.fail(
          &t, at.key("center"),
          std::string("a disk needs center = [a, b] (m, on the cloth plane's ") + axes + " axes)");
    if (!t.get("radius")) r.fail(&t, at.key("radius"), "a disk needs radius = r (m)");
    const auto center = r.number_pair(at, "center", {0, 0}, kAnyNumber);
    c.disk_center_x = center[0];
    c.disk_center_z = center[1];
    c.disk_radius = r.number(at, "radius", 0.0, kPositive);
    const std::vector<std::uint8_t> mask = held_mask(cloth, {c});
    if (std::none_of(mask.begin(), mask.end(), [](std::uint8_t m) { return m != 0; }))
      r.fail(t.get("radius"), at.key("radius"),
             "expected a disk that covers at least one particle, got radius " +
                 toml_double(c.disk_radius) + " m around [" + toml_double(center[0]) + ", " +
                 toml_double(center[1]) + "] (" + axes + "), which holds none");
  }

  if (c.select == "indices") {
    const toml::node* n = t.get("list");
    if (!n) r.fail(&t, at.key("list"), "select = \"indices\" needs list = [[i, j], ...]");
    const toml::array* list = n->as_array();
    if (!list || list->empty())
      r.expected(*n, at.key("list"), "a non-empty array of [i, j] grid indices");
    for (size_t k = 0; k < list->size(); ++k) {
      const toml::node& e = *list->get(k);
      const std::string key = at.key("list") + "." + std::to_string(k);
      const auto ij = Reader::int_pair(e, std::numeric_limits<int>::min());
      if (!ij) r.expected(e, key, "an [i, j] pair of integers");
      const auto [i, j] = *ij;
      if (i < 0 || i >= cloth.nu || j < 0 || j >= cloth.nv)
        r.fail(&e, key,
               "expected a grid index with i in 0.." + std::to_string(cloth.nu - 1) +
                   " and j in 0.." + std::to_string(cloth.nv - 1) + " (the grid has " +
                   std::to_string(cloth.nu) + " x " + std::to_string(cloth.nv) +
                   " particles), got " + describe(e));
      c.indices.emplace_back(i, j);
    }
  }
  return c;
}

cloth::Sphere read_sphere(const Reader& r, const toml::table& t, const std::string& path) {
  const At at{t, path};
  r.check_keys(at, kSphereKeys);
  cloth::Sphere s;
  s.center = r.vec3(at, "center", s.center);
  s.radius = r.number(at, "radius", s.radius, kPositive);
  s.restitution = r.number(at, "restitution", s.restitution, kUnitInterval);
  s.friction = r.number(at, "friction", s.friction, kNonNegative);
  s.velocity = r.vec3(at, "velocity", s.velocity);
  s.margin = r.number(at, "margin", s.margin, kNonNegative);
  return s;
}

/// An engine; label is how messages name it until its name is known.
EngineSpec read_engine(const Reader& r, const toml::table& t, int index) {
  EngineSpec e;
  const toml::node* name = t.get("name");
  // messages name the engine by its given name once that is valid, else by its index
  std::string path = "engine." + std::to_string(index);
  if (name) {
    const std::string s = r.string({t, path}, "name", "");
    if (!valid_engine_name(s))
      r.expected(*name, path + ".name", "a name of letters, digits, '-', '_' or '+'");
    path = "engine." + s;
  }
  const At first{t, path};
  e.kind = r.choice(first, "kind", e.kind, kEngineKinds);
  if (e.kind == "custom") {
    const std::string integrator = r.choice(
        first, "integrator", cloth::integrator_name(e.solver.integrator), integrator_names());
    e.solver.integrator = *cloth::parse_integrator(integrator);
  }
  e.name = name ? name->as_string()->get()
                : derived_engine_name(e.kind, cloth::integrator_name(e.solver.integrator));
  const At at{t, "engine." + e.name};

  // keys of another kind of engine are named as such
  const Keys& own = engine_kind_keys(e.kind);
  Keys known = kEngineCommonKeys;
  known.insert(known.end(), own.begin(), own.end());
  const toml::node* kind = t.get("kind");
  const std::string kind_source = from_override(kind) ? " (" + *kind->source().path + ")" : "";
  for (const auto& [k, v] : t) {
    if (contains(known, k.str())) continue;
    for (std::string_view other : kEngineKinds)
      if (contains(engine_kind_keys(other), k.str()))
        r.fail(&v, at.key(k.str()),
               "applies only to " + std::string(other) + " engines, this one is " + e.kind +
                   kind_source);
    r.fail(&v, at.key(k.str()), "unknown key" + suggest(k.str(), known));
  }

  e.dt = r.number(at, "dt", e.dt, kPositive);
  if (e.kind == "custom") {
    cloth::SolverOptions& o = e.solver;
    o.newton_iterations = r.integer(at, "newton_iterations", o.newton_iterations, 1);
    o.cg_tolerance = r.number(at, "cg_tolerance", o.cg_tolerance, kPositive);
    o.cg_max_iterations = r.integer(at, "cg_max_iterations", o.cg_max_iterations, 1);
    o.clamp_compressed = r.boolean(at, "clamp_compressed", o.clamp_compressed);
  } else if (e.kind == "bullet-deformable") {
    BulletOptions& o = e.bullet;
    o.implicit = r.boolean(at, "implicit", o.implicit);
    o.line_search = r.boolean(at, "line_search", o.line_search);
    o.projection = r.boolean(at, "projection", o.projection);
  } else {
    BulletOptions& o = e.bullet;
    o.stiffness = r.choice(at, "stiffness", o.stiffness, kSoftbodyStiffness);
    o.klst = r.number(at, "klst", o.klst, kUnitInterval);
    o.iterations = r.integer(at, "iterations", o.iterations, 1);
  }
  return e;
}

Scenario read_scenario(const toml::table& root, const std::string& source,
                       const std::vector<std::string>& only) {
  const Reader r(source);
  const At at{root, ""};
  r.check_keys(at, kTopKeys);
  Scenario s;
  s.source = source;

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
  s.snapshot_interval = r.number(at, "snapshot_interval", s.snapshot_interval, kNonNegative);
  if (s.snapshot_interval > 0 && !whole_multiple(s.snapshot_interval, s.frame_interval)) {
    const auto [n, key] = blame({{root.get("snapshot_interval"), "snapshot_interval"},
                                 {root.get("frame_interval"), "frame_interval"}});
    r.fail(n, key,
           "expected snapshot_interval to be 0 or a whole multiple of frame_interval = " +
               toml_double(s.frame_interval) +
               " s, got snapshot_interval = " + toml_double(s.snapshot_interval) + " s");
  }
  s.blowup_strain = r.number(at, "blowup_strain", s.blowup_strain, kPositive);
  s.scene.gravity = r.vec3(at, "gravity", s.scene.gravity);

  // the scene
  s.scene.cloth = read_cloth(r, r.table(at, "cloth"));
  const auto constraints = r.tables(at, "constraint");
  for (size_t k = 0; k < constraints.size(); ++k)
    s.constraints.push_back(
        read_constraint(r, *constraints[k], "constraint." + std::to_string(k), s.scene.cloth));
  s.scene.held = held_mask(s.scene.cloth, s.constraints);
  const auto spheres = r.tables(at, "sphere");
  for (size_t k = 0; k < spheres.size(); ++k)
    s.scene.spheres.push_back(read_sphere(r, *spheres[k], "sphere." + std::to_string(k)));

  // the engines
  const auto engines = r.tables(at, "engine");
  if (engines.empty())
    r.fail(root.get("engine") ? root.get("engine") : &root, "engine",
           "expected at least one [[engine]], got none");
  std::map<std::string, int> first_with_name;
  for (size_t k = 0; k < engines.size(); ++k) {
    const toml::table& t = *engines[k];
    EngineSpec e = read_engine(r, t, static_cast<int>(k));
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
    s.engines.push_back(std::move(e));
  }

  // the reference engine, by name; the first one unless given
  s.reference = s.engines.front().name;
  if (const toml::node* n = root.get("reference")) {
    s.reference = r.string(at, "reference", "");
    Keys names;
    for (const EngineSpec& e : s.engines) names.push_back(e.name);
    if (!contains(names, s.reference))
      r.fail(n, "reference",
             "expected the name of an engine, got " + toml_string(s.reference) +
                 suggest(s.reference, names));
  }

  // the engines asked for (and the reference) stay; only they must be able to model the scene
  Keys names;
  for (const EngineSpec& e : s.engines) names.push_back(e.name);
  for (const std::string& name : only)
    if (!contains(names, name))
      throw ScenarioError(source, "engine",
                          "expected the name of one of the scenario's engines, got " +
                              toml_string(name) + suggest(name, names));
  std::vector<EngineSpec> kept;
  for (size_t k = 0; k < s.engines.size(); ++k) {
    EngineSpec& e = s.engines[k];
    if (!only.empty() && e.name != s.reference &&
        std::find(only.begin(), only.end(), e.name) == only.end())
      continue;
    if (const std::string why = engine_limitation(e, s.scene); !why.empty()) {
      const toml::table& t = *engines[k];
      const auto stiffness = root["cloth"]["stiffness"];
      const auto [n, key] =
          blame({{t.get("kind") ? t.get("kind") : &t, "engine." + e.name + ".kind"},
                 {stiffness["structural"].node(), "cloth.stiffness.structural"},
                 {stiffness["shear"].node(), "cloth.stiffness.shear"}});
      r.fail(n, key, why);
    }
    // the Bullet adapters know what else they cannot honour (restitution, differing margins,
    // option combinations): building one now turns a refusal into an error at the engine
    if (e.kind != "custom") {
      try {
        make_engine(e, s.scene);
      } catch (const std::invalid_argument& refusal) {
        const toml::table& t = *engines[k];
        r.fail(t.get("kind") ? t.get("kind") : &t, "engine." + e.name, refusal.what());
      }
    }
    kept.push_back(std::move(e));
  }
  s.engines = std::move(kept);
  return s;
}

// ---- --set overrides

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return "";
  return std::string(s.substr(b, s.find_last_not_of(" \t") - b + 1));
}

/// One TOML value, parsed so that its source reads "--set key"; a bare word is a string.
toml::table parse_value(const std::string& text, const std::string& where) {
  const auto one_value = [&](const std::string& doc) {
    toml::table t = toml::parse("v = " + doc + "\n", where);
    if (t.size() != 1 || !t.contains("v"))
      throw ScenarioError(where, "", "expected one TOML value after '=', got " + text);
    return t;
  };
  try {
    return one_value(text);
  } catch (const toml::parse_error& e) {
    // what looks like structured TOML must be TOML; anything else is a bare word
    if (std::string_view("[{\"'").find(text.front()) != std::string_view::npos ||
        text.find('\n') != std::string::npos)
      throw ScenarioError(
          where, "", "cannot read the value " + text + " as TOML: " + std::string(e.description()));
  }
  return one_value(toml_string(text));
}

/// The table at parent[key], created from init (TOML) when absent.
toml::table& child_table(toml::table& parent, const std::string& key, const std::string& where,
                         const std::string& init = "{}") {
  if (toml::node* n = parent.get(key)) {
    if (toml::table* t = n->as_table()) return *t;
    throw ScenarioError(where, "", key + " is " + describe(*n) + " in the scenario, not a table");
  }
  toml::table holder = parse_value(init, where);
  parent.insert_or_assign(key, std::move(*holder.get("v")));
  return *parent.get(key)->as_table();
}

/// The index of the [[top]] entry that a --set key's second part names.
size_t entry_index(toml::array* entries, const std::string& top, const std::string& id,
                   const std::string& where) {
  const size_t count = entries ? entries->size() : 0;
  Keys names;
  std::vector<std::string> storage;
  if (top == "engine" && entries) {
    for (size_t k = 0; k < count; ++k)
      if (const toml::table* t = entries->get(k)->as_table())
        storage.push_back(engine_table_name(*t));
    for (size_t k = 0; k < storage.size(); ++k)
      if (storage[k] == id) return k;
    names.assign(storage.begin(), storage.end());
  }
  const bool digits = !id.empty() && id.size() < 9 &&
                      std::all_of(id.begin(), id.end(), [](char c) { return std::isdigit(c); });
  if (digits && std::stoul(id) < count) return std::stoul(id);
  if (top == "engine")
    throw ScenarioError(
        where, "",
        "no engine named " + toml_string(id) + (names.empty() ? "" : suggest(id, names)));
  throw ScenarioError(where, "",
                      "no " + top + " " + id + ": the scenario has " + std::to_string(count) +
                          " [[" + top + "]], counted from 0");
}

void apply_override(toml::table& root, const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos)
    throw ScenarioError(kOverridePrefix + text, "",
                        "expected KEY=VALUE, e.g. --set cloth.damping=0");
  const std::string key = trim(std::string_view(text).substr(0, eq));
  const std::string value_text = trim(std::string_view(text).substr(eq + 1));
  const std::string where = kOverridePrefix + key;
  if (key.empty()) throw ScenarioError(kOverridePrefix + text, "", "expected a key before '='");
  if (value_text.empty()) throw ScenarioError(where, "", "expected a value after '='");
  std::vector<std::string> part;
  for (size_t b = 0;;) {
    const size_t e = key.find('.', b);
    part.push_back(key.substr(b, e - b));
    if (part.back().empty())
      throw ScenarioError(where, "", "expected a dotted key such as cloth.damping");
    if (e == std::string::npos) break;
    b = e + 1;
  }
  const auto unknown = [&](const std::string& k, const Keys& known, const std::string& in) {
    return ScenarioError(
        where, "",
        "unknown key " + toml_string(k) + (in.empty() ? "" : " in " + in) + suggest(k, known));
  };
  const auto not_a_table = [&](size_t depth) {
    std::string k = part[0];
    for (size_t d = 1; d < depth; ++d) k += "." + part[d];
    return ScenarioError(where, "", k + " is a single value, it has no keys");
  };
  const std::string& top = part[0];
  if (!contains(kTopKeys, top)) throw unknown(top, kTopKeys, "");
  toml::table holder = parse_value(value_text, where);
  toml::node& value = *holder.get("v");

  if (part.size() == 1) {
    root.insert_or_assign(top, std::move(value));
  } else if (top == "cloth") {
    toml::table& cloth = child_table(root, "cloth", where);
    if (!contains(kClothKeys, part[1])) throw unknown(part[1], kClothKeys, "cloth");
    if (part[1] == "stiffness" && part.size() >= 3) {
      if (!contains(kStiffnessKeys, part[2]))
        throw unknown(part[2], kStiffnessKeys, "cloth.stiffness");
      if (part.size() > 3) throw not_a_table(3);
      // a missing table means the default stiffnesses; change just the one named
      const cloth::ClothParams d;
      toml::table& st = child_table(cloth, "stiffness", where,
                                    "{ structural = " + toml_double(d.k_structural) +
                                        ", shear = " + toml_double(d.k_shear) +
                                        ", bend = " + toml_double(d.k_bend) + " }");
      st.insert_or_assign(part[2], std::move(value));
      return;
    }
    if (part.size() > 2) throw not_a_table(2);
    // the two ways of giving the mass replace each other
    if (part[1] == "particle_mass") cloth.erase("total_mass");
    if (part[1] == "total_mass") cloth.erase("particle_mass");
    cloth.insert_or_assign(part[1], std::move(value));
  } else if (top == "constraint" || top == "sphere" || top == "engine") {
    toml::node* list = root.get(top);
    const size_t k = entry_index(list ? list->as_array() : nullptr, top, part[1], where);
    toml::array& entries = *list->as_array();
    if (part.size() == 2) {
      entries.replace(entries.cbegin() + static_cast<std::ptrdiff_t>(k), std::move(value));
      return;
    }
    const Keys known = top == "constraint" ? kConstraintKeys
                       : top == "sphere"   ? kSphereKeys
                                           : all_engine_keys();
    if (!contains(known, part[2])) throw unknown(part[2], known, top + "." + part[1]);
    if (part.size() > 3) throw not_a_table(3);
    toml::table* entry = entries.get(k)->as_table();
    if (!entry) throw ScenarioError(where, "", top + "." + part[1] + " is not a table");
    entry->insert_or_assign(part[2], std::move(value));
  } else {
    throw not_a_table(1);
  }
}

// ---- writing

std::string vec(std::initializer_list<double> xs) {
  std::string s = "[";
  for (double x : xs) s += (s.size() > 1 ? ", " : "") + toml_double(x);
  return s + "]";
}

}  // namespace

std::string engine_limitation(const EngineSpec& engine, const cloth::Scene& scene) {
  const cloth::ClothParams& c = scene.cloth;
  // only a grid with both kinds of spring has two stiffnesses to tell apart: a chain
  // (one particle wide) has no shear springs, nor has a cloth whose shear stiffness is 0
  const bool has_structural = c.k_structural > 0.0;
  const bool has_shear = c.k_shear > 0.0 && c.nu > 1 && c.nv > 1;
  if (engine.kind == "bullet-deformable" && has_structural && has_shear &&
      c.k_structural != c.k_shear)
    return "bullet-deformable cannot model this scene: its mass-spring force has one stiffness "
           "for structural and shear springs, but cloth.stiffness has structural = " +
           toml_double(c.k_structural) + " and shear = " + toml_double(c.k_shear) +
           " N/m (make them equal, or run this scene on other engines)";
  return "";
}

Scenario parse_scenario(std::string_view toml_text, const std::string& source_name,
                        const std::vector<std::string>& overrides,
                        const std::vector<std::string>& only) {
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
  return read_scenario(root, source_name, only);
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

std::string scenario_to_toml(const Scenario& s) {
  std::ostringstream o;
  const auto d = [](double x) { return toml_double(x); };
  o << "# the fully resolved scenario: every key, with defaults and overrides filled in\n"
    << "name = " << toml_string(s.name) << "\n"
    << "description = " << toml_string(s.description) << "\n"
    << "duration = " << d(s.duration) << "  # s\n"
    << "frame_interval = " << d(s.frame_interval) << "  # s\n"
    << "snapshot_interval = " << d(s.snapshot_interval) << "  # s\n"
    << "blowup_strain = " << d(s.blowup_strain) << "\n"
    << "reference = "
    << toml_string(!s.reference.empty() || s.engines.empty() ? s.reference : s.engines.front().name)
    << "\n";
  const cloth::Vector3& g = s.scene.gravity;
  o << "gravity = " << vec({g.x(), g.y(), g.z()}) << "  # m/s^2\n";

  const cloth::ClothParams& c = s.scene.cloth;
  o << "\n[cloth]\n"
    << "particles = [" << c.nu << ", " << c.nv << "]\n"
    << "size = " << vec({c.size_u, c.size_v}) << "  # m\n"
    << "center = " << vec({c.center.x(), c.center.y(), c.center.z()}) << "  # m\n"
    << "plane = " << (c.plane == cloth::Plane::xz ? "\"xz\"" : "\"xy\"") << "\n";
  if (c.total_mass > 0)
    o << "total_mass = " << d(c.total_mass) << "  # kg\n";
  else
    o << "particle_mass = " << d(c.particle_mass) << "  # kg\n";
  o << "stiffness = { structural = " << d(c.k_structural) << ", shear = " << d(c.k_shear)
    << ", bend = " << d(c.k_bend) << " }  # N/m\n"
    << "damping = " << d(c.damping) << "  # N s/m\n"
    << "air_drag = " << d(c.air_drag) << "  # N s/m\n";

  for (const ConstraintSpec& k : s.constraints) {
    o << "\n[[constraint]]\n"
      << "select = " << toml_string(k.select) << "\n"
      << "hold = " << toml_string(hold_letters(k.hold)) << "\n";
    if (k.select == "disk")
      o << "center = " << vec({k.disk_center_x, k.disk_center_z}) << "  # m\n"
        << "radius = " << d(k.disk_radius) << "  # m\n";
    if (k.select == "indices") {
      o << "list = [";
      for (size_t p = 0; p < k.indices.size(); ++p)
        o << (p ? ", " : "") << "[" << k.indices[p].first << ", " << k.indices[p].second << "]";
      o << "]\n";
    }
  }

  for (const cloth::Sphere& sp : s.scene.spheres) {
    o << "\n[[sphere]]\n"
      << "center = " << vec({sp.center.x(), sp.center.y(), sp.center.z()}) << "  # m\n"
      << "radius = " << d(sp.radius) << "  # m\n"
      << "restitution = " << d(sp.restitution) << "\n"
      << "friction = " << d(sp.friction) << "\n"
      << "velocity = " << vec({sp.velocity.x(), sp.velocity.y(), sp.velocity.z()}) << "  # m/s\n"
      << "margin = " << d(sp.margin) << "  # m\n";
  }

  for (const EngineSpec& e : s.engines) {
    o << "\n[[engine]]\n"
      << "name = " << toml_string(e.name) << "\n"
      << "kind = " << toml_string(e.kind) << "\n"
      << "dt = " << d(e.dt) << "  # s\n";
    if (e.kind == "custom") {
      o << "integrator = " << toml_string(cloth::integrator_name(e.solver.integrator)) << "\n"
        << "newton_iterations = " << e.solver.newton_iterations << "\n"
        << "cg_tolerance = " << d(e.solver.cg_tolerance) << "\n"
        << "cg_max_iterations = " << e.solver.cg_max_iterations << "\n"
        << "clamp_compressed = " << (e.solver.clamp_compressed ? "true" : "false") << "\n";
    } else if (e.kind == "bullet-deformable") {
      o << "implicit = " << (e.bullet.implicit ? "true" : "false") << "\n"
        << "line_search = " << (e.bullet.line_search ? "true" : "false") << "\n"
        << "projection = " << (e.bullet.projection ? "true" : "false") << "\n";
    } else if (e.kind == "bullet-softbody") {
      o << "stiffness = " << toml_string(e.bullet.stiffness) << "\n"
        << "klst = " << d(e.bullet.klst) << "\n"
        << "iterations = " << e.bullet.iterations << "\n";
    }
  }
  return o.str();
}

}  // namespace clothbench
