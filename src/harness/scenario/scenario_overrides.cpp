#include "harness/scenario/scenario_overrides.hpp"

#include <algorithm>
#include <cctype>
#include <memory>
#include <optional>
#include <vector>

#include "cloth/model/model.hpp"
#include "cloth/model/scene.hpp"
#include "harness/scenario/toml_reader.hpp"

namespace clothbench {

namespace {

/// The name an [[engine]] table goes by (given or derived), for --set addressing.
std::string engine_table_name(const toml::table& t) {
  if (auto name = t["name"].value<std::string>()) return *name;
  const std::string kind = t["kind"].value_or(std::string("custom"));
  const std::string integrator = t["integrator"].value_or(std::string("rk4"));
  const auto k = parse_engine_kind(kind);
  const auto i = cloth::parse_integrator(integrator);
  // a misspelt kind or integrator is refused when the scenario is read; until then it names
  if (!k) return kind;
  if (*k == EngineKind::custom && !i) return "custom-" + integrator;
  return derived_engine_name(*k, i.value_or(cloth::Integrator::rk4));
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return "";
  return std::string(s.substr(b, s.find_last_not_of(" \t") - b + 1));
}

/// One TOML value, parsed so that its source reads "--set key"; a bare word is a string.
toml::table parse_value(const std::string& text, const std::string& where) {
  if (const auto problem = toml_structure_problem(text))
    throw ScenarioError(where, "", "cannot read the value: " + problem->second);
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
  // a bare word: quoted, it can still fail (invalid UTF-8, found by scripts/fuzz)
  try {
    return one_value(toml_string(text));
  } catch (const toml::parse_error& e) {
    throw ScenarioError(where, "",
                        "cannot read the value as a string: " + std::string(e.description()));
  }
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

/// The keys of one entry of the [[top]] array of tables; nullopt when top is not one.
std::optional<Keys> entry_keys(const std::string& top) {
  if (top == "constraint") return kConstraintKeys;
  if (top == "sphere") return kSphereKeys;
  if (top == "handle") return kHandleKeys;
  if (top == "engine") return all_engine_keys();
  const std::pair<const char*, const Keys*> shapes[] = {{"plane", &kPlaneKeys},
                                                        {"box", &kBoxKeys},
                                                        {"capsule", &kCapsuleKeys},
                                                        {"cylinder", &kCylinderKeys}};
  for (const auto& [name, own] : shapes) {
    if (top != name) continue;
    Keys k = *own;
    k.insert(k.end(), kColliderKeys.begin(), kColliderKeys.end());
    return k;
  }
  return std::nullopt;
}

}  // namespace

namespace {

/// The error of a --set key that names no key of the table in.
ScenarioError unknown_key(const std::string& where, const std::string& k, const Keys& known,
                          const std::string& in) {
  return ScenarioError(
      where, "",
      "unknown key " + toml_string(k) + (in.empty() ? "" : " in " + in) + suggest(k, known));
}

/// The error of a --set key that goes below a single value, at its depth-th part.
ScenarioError single_value(const std::string& where, const std::vector<std::string>& part,
                           size_t depth) {
  std::string k = part[0];
  for (size_t d = 1; d < depth; ++d) k += "." + part[d];
  return ScenarioError(where, "", k + " is a single value, it has no keys");
}

/// The parts of a dotted --set key; throws for an empty part.
std::vector<std::string> key_parts(const std::string& key, const std::string& where) {
  std::vector<std::string> part;
  for (size_t b = 0;;) {
    const size_t e = key.find('.', b);
    part.push_back(key.substr(b, e - b));
    if (part.back().empty())
      throw ScenarioError(where, "", "expected a dotted key such as cloth.damping");
    if (e == std::string::npos) break;
    b = e + 1;
  }
  return part;
}

/// cloth.KEY, cloth.stiffness.KIND or cloth.generate.KEY set to value.
void set_cloth_key(toml::table& root, const std::vector<std::string>& part, toml::node&& value,
                   const std::string& where) {
  toml::table& cloth = child_table(root, "cloth", where);
  if (!contains(kClothKeys, part[1])) throw unknown_key(where, part[1], kClothKeys, "cloth");
  if (part[1] == "stiffness" && part.size() >= 3) {
    if (!contains(kStiffnessKeys, part[2]))
      throw unknown_key(where, part[2], kStiffnessKeys, "cloth.stiffness");
    if (part.size() > 3) throw single_value(where, part, 3);
    // a missing table means the default stiffnesses (a fabric's: its own); change just the one
    const cloth::ClothParams d;
    toml::table& st =
        child_table(cloth, "stiffness", where,
                    cloth.contains("fabric") ? std::string("{}")
                                             : "{ structural = " + toml_double(d.k_structural) +
                                                   ", shear = " + toml_double(d.k_shear) +
                                                   ", bend = " + toml_double(d.k_bend) + " }");
    st.insert_or_assign(part[2], std::move(value));
    return;
  }
  if (part[1] == "generate" && part.size() >= 3) {
    // one key of the generated shape
    if (!contains(kGenerateKeys, part[2]))
      throw unknown_key(where, part[2], kGenerateKeys, "cloth.generate");
    if (part.size() > 3) throw single_value(where, part, 3);
    child_table(cloth, "generate", where).insert_or_assign(part[2], std::move(value));
    return;
  }
  if (part.size() > 2) throw single_value(where, part, 2);
  // the three ways of giving the mass replace each other
  for (const char* mass : {"particle_mass", "total_mass", "areal_density"})
    if (part[1] == mass)
      for (const char* other : {"particle_mass", "total_mass", "areal_density"})
        if (part[1] != other) cloth.erase(other);
  cloth.insert_or_assign(part[1], std::move(value));
}

}  // namespace

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
  const std::vector<std::string> part = key_parts(key, where);
  const std::string& top = part[0];
  if (!contains(kTopKeys, top)) throw unknown_key(where, top, kTopKeys, "");
  toml::table holder = parse_value(value_text, where);
  toml::node& value = *holder.get("v");

  if (part.size() == 1) {
    root.insert_or_assign(top, std::move(value));
  } else if (top == "cloth") {
    set_cloth_key(root, part, std::move(value), where);
  } else if (top == "test") {
    // test.kind, test.edge: a key of the [test] table (created when the file has none)
    if (!contains(kTestKeys, part[1])) throw unknown_key(where, part[1], kTestKeys, "test");
    if (part.size() > 2) throw single_value(where, part, 2);
    child_table(root, "test", where).insert_or_assign(part[1], std::move(value));
  } else if (const std::optional<Keys> known = entry_keys(top)) {
    toml::node* list = root.get(top);
    const size_t k = entry_index(list ? list->as_array() : nullptr, top, part[1], where);
    toml::array& entries = *list->as_array();
    if (part.size() == 2) {
      entries.replace(entries.cbegin() + static_cast<std::ptrdiff_t>(k), std::move(value));
      return;
    }
    if (!contains(*known, part[2])) throw unknown_key(where, part[2], *known, top + "." + part[1]);
    if (part.size() > 3) throw single_value(where, part, 3);
    toml::table* entry = entries.get(k)->as_table();
    if (!entry) throw ScenarioError(where, "", top + "." + part[1] + " is not a table");
    entry->insert_or_assign(part[2], std::move(value));
  } else {
    throw single_value(where, part, 1);
  }
}

std::string as_option_error(const std::string& message, const std::string& key,
                            const std::string& option) {
  const std::string as_set = kOverridePrefix + key + ": ";
  return option + ": " + (message.rfind(as_set, 0) == 0 ? message.substr(as_set.size()) : message);
}

// ---- an [[engine]]'s own overrides

const Keys kEngineOverrideTops = {"cloth", "gravity", "wind",    "sphere",
                                  "plane", "box",     "capsule", "cylinder"};

std::optional<std::string> override_value_text(const toml::node& n) {
  if (const auto* v = n.as_floating_point()) return toml_double(v->get());
  if (const auto* v = n.as_integer()) return std::to_string(v->get());
  if (const auto* v = n.as_boolean()) return std::string(v->get() ? "true" : "false");
  if (const auto* v = n.as_string()) return toml_string(v->get());
  const toml::array* a = n.as_array();
  if (!a) return std::nullopt;
  std::string text = "[";
  for (size_t k = 0; k < a->size(); ++k) {
    const auto item = override_value_text(*a->get(k));
    if (!item) return std::nullopt;
    text += (k ? ", " : "") + *item;
  }
  return text + "]";
}

namespace {

/// Refuses an override key whose first part is not a scene key, saying where it belongs.
void check_override_top(const Reader& r, const toml::node& value, const std::string& path,
                        const std::string& key) {
  const std::string top = key.substr(0, key.find('.'));
  if (top == "engine")
    r.fail(&value, path,
           "an engine's own keys go in its [[engine]] table, not in its overrides, got " +
               toml_string(key));
  if (!contains(kEngineOverrideTops, top))
    r.fail(&value, path,
           "an engine may override the scene's physics only (keys under cloth, gravity, wind, "
           "sphere, plane, box, capsule, cylinder), got " +
               toml_string(key));
}

/// The entries of t by dotted path: { "cloth.damping" = 0 } and { cloth.damping = 0 } alike.
std::vector<std::pair<std::string, const toml::node*>> flat_entries(const toml::table& t,
                                                                    const std::string& prefix) {
  std::vector<std::pair<std::string, const toml::node*>> out;
  for (const auto& [k, v] : t) {
    const std::string key = path_of(prefix, k.str());
    if (const toml::table* inner = v.as_table()) {
      const auto more = flat_entries(*inner, key);
      out.insert(out.end(), more.begin(), more.end());
    } else {
      out.emplace_back(key, &v);
    }
  }
  return out;
}

/// root for engine k alone: its table without its overrides, no reference.
toml::table solo_root(const toml::table& root, const toml::table& engine) {
  toml::table own = root;
  own.erase("reference");
  toml::table t = engine;
  t.erase("overrides");
  toml::array solo;
  solo.push_back(std::move(t));
  own.insert_or_assign("engine", std::move(solo));
  return own;
}

/// Reads one engine's overrides table n into e, its scene from read.
void read_one(const Reader& r, const toml::table& root, const toml::table& engine,
              const toml::node& n, const Scenario& s, EngineSpec& e,
              const std::function<Scenario(const toml::table&)>& read) {
  const std::string path = "engine." + e.name + ".overrides";
  const toml::table* table = n.as_table();
  if (!table)
    r.expected(n, path, "a table of --set key paths and values, e.g. { \"cloth.damping\" = 0 }");
  toml::table own = solo_root(root, engine);
  // each key as --set would apply it, the message naming the engine's key
  for (const auto& [key, v] : flat_entries(*table, "")) {
    const std::string at = path + "." + toml_string(key);
    check_override_top(r, *v, at, key);
    const std::optional<std::string> text = override_value_text(*v);
    if (!text) r.expected(*v, at, "a number, string, boolean or array");
    try {
      apply_override(own, key + "=" + *text);
    } catch (const ScenarioError& x) {
      r.fail(v, at, x.problem());
    }
    e.overrides.emplace_back(key, *text);
  }
  // the whole scene read again with them; a value a key refuses names the engine
  Scenario mine;
  try {
    mine = read(own);
  } catch (const ScenarioError& x) {
    const std::string w = x.where();
    const std::string what = w.rfind(kOverridePrefix, 0) == 0
                                 ? w.substr(std::string(kOverridePrefix).size()) + ": "
                                 : (x.key().empty() ? "" : x.key() + ": ");
    r.fail(&n, path, what + x.problem());
  }
  if (cloth::rest_positions(mine.scene) != cloth::rest_positions(s.scene) ||
      mine.scene.held != s.scene.held)
    r.fail(&n, path,
           "changes the cloth's rest shape or its held particles; an engine's overrides may "
           "change its material and forces only");
  e.scene = std::make_shared<const cloth::Scene>(std::move(mine.scene));
}

}  // namespace

void read_engine_overrides(const Reader& r, const toml::table& root,
                           const std::vector<const toml::table*>& engines, Scenario& s,
                           const std::function<Scenario(const toml::table&)>& read) {
  for (size_t k = 0; k < engines.size() && k < s.engines.size(); ++k)
    if (const toml::node* n = engines[k]->get("overrides"))
      read_one(r, root, *engines[k], *n, s, s.engines[k], read);
}

}  // namespace clothbench
