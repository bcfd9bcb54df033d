#include "harness/scenario/engine_overrides.hpp"

#include <optional>
#include <sstream>

#include "cloth/model/model.hpp"
#include "harness/scenario/scenario_overrides.hpp"

namespace clothbench {

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
