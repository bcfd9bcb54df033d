#pragma once
/// @file toml_reader.hpp
/// Typed reads from a parsed TOML table with located errors: every value a user can get wrong
/// is checked where it is read, and a bad one is a ScenarioError naming the file and line (or
/// the --set override), the dotted key, what was expected and what was found.

#include <toml++/toml.h>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cloth/model/types.hpp"
#include "format/number_format.hpp"
#include "harness/io/toml_text.hpp"
#include "harness/scenario/did_you_mean.hpp"
#include "harness/scenario/scenario_error.hpp"
#include "harness/scenario/scenario_format.hpp"

namespace clothbench {

using cloth::toml_double;

/// How the source of a value set by --set starts ("--set cloth.damping").
inline constexpr const char* kOverridePrefix = "--set ";

/// True when n was put there by a --set override.
inline bool from_override(const toml::node* n) {
  return n && n->source().path && n->source().path->rfind(kOverridePrefix, 0) == 0;
}

/// prefix.key, or key alone at the top.
inline std::string path_of(const std::string& prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : prefix + "." + std::string(key);
}

/// A range a number must lie in, as said in messages ("> 0").
struct Bound {
  const char* text;  // "" for any finite number
  bool (*ok)(double);
};
inline const Bound kAnyNumber{"", [](double) { return true; }};
inline const Bound kPositive{"> 0", [](double x) { return x > 0; }};
inline const Bound kNonNegative{">= 0", [](double x) { return x >= 0; }};
inline const Bound kUnitInterval{"in [0, 1]", [](double x) { return x >= 0 && x <= 1; }};
// magnitudes a cloth scene can have: a subnormal or astronomical value would be simulated and
// called stable (a cloth thrown to 1e300 m, a gravity under which an engine never moves), so it
// is refused with the range that makes sense
inline const Bound kLength{"from 1e-6 to 1e4", [](double x) { return x >= 1e-6 && x <= 1e4; }};
inline const Bound kSize{"0, or from 1e-6 to 1e4",
                         [](double x) { return x == 0 || (x >= 1e-6 && x <= 1e4); }};
inline const Bound kMass{"from 1e-9 to 1e6", [](double x) { return x >= 1e-9 && x <= 1e6; }};
inline const Bound kShell{"from 0 to 1", [](double x) { return x >= 0 && x <= 1; }};
inline const Bound kAcceleration{"from -1e4 to 1e4", [](double x) { return std::abs(x) <= 1e4; }};
// a grid lattice's angle: the rectangle's edges along the yarns or the squares' diagonals
inline const Bound kMultipleOf45{
    "a multiple of 45 from -360 to 360",
    [](double x) { return std::abs(x) <= 360 && std::abs(x / 45 - std::round(x / 45)) <= 1e-12; }};

inline std::string expected_number(const Bound& b) {
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
    if (x && !std::isfinite(*x))
      fail(n, at.key(key), "must be finite (" + expected_number(b) + "), got " + describe(*n));
    if (!x || !b.ok(*x)) expected(*n, at.key(key), expected_number(b));
    return *x;
  }

  int integer(const At& at, std::string_view key, int def, int min) const {
    const toml::node* n = at.table.get(key);
    if (!n) return def;
    const std::optional<int> i = as_int(*n, min);
    if (!i && has_huge_integer(*n))
      fail(n, at.key(key),
           "too large: at most " + std::to_string(std::numeric_limits<int>::max()) + ", got " +
               describe(*n));
    if (!i) expected(*n, at.key(key), "an integer >= " + std::to_string(min));
    return *i;
  }

  /// An integer in [min, max].
  int integer(const At& at, std::string_view key, int def, int min, int max) const {
    const int i = integer(at, key, def, min);
    if (i > max)
      fail(at.table.get(key), at.key(key),
           "expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) +
               "], got " + std::to_string(i));
    return i;
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

  cloth::Vector3 vec3(const At& at, std::string_view key, const cloth::Vector3& def,
                      const Bound& b = kAnyNumber) const {
    const toml::node* n = at.table.get(key);
    if (!n) return def;
    const auto v = numbers(*n, 3, b);
    if (!v)
      expected(*n, at.key(key), "an array of 3 numbers" + std::string(*b.text ? " " : "") + b.text);
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

  /// True when n is an integer, or an array holding one, past what an int holds.
  static bool has_huge_integer(const toml::node& n) {
    if (const auto* i = n.as_integer()) return i->get() > std::numeric_limits<int>::max();
    if (const toml::array* a = n.as_array())
      for (const toml::node& e : *a)
        if (has_huge_integer(e)) return true;
    return false;
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
inline std::pair<const toml::node*, std::string> blame(
    std::initializer_list<std::pair<const toml::node*, std::string>> places) {
  for (const auto& p : places)
    if (from_override(p.first)) return p;
  for (const auto& p : places)
    if (p.first) return p;
  return *places.begin();
}

}  // namespace clothbench
