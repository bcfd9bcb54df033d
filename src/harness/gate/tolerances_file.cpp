#include "harness/gate/tolerances_file.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "harness/io/text_file.hpp"
#include "harness/io/toml_text.hpp"
#include "harness/io/user_error.hpp"
#include "harness/scenario/scenario_format.hpp"

namespace clothbench {

namespace fs = std::filesystem;

const std::vector<std::string> kMetricQuantities = {"stable",
                                                    "steps",
                                                    "force_evals",
                                                    "cg_iterations",
                                                    "max_energy_error",
                                                    "final_rms_vs_reference",
                                                    "max_rms_vs_reference",
                                                    "drape_coefficient",
                                                    "final_com_y"};

namespace {

std::string read_tolerance_text(const fs::path& p) {
  return read_existing_text(p.string());
}

/// "FILE:LINE: KEY: " for a message about the node at key.
std::string where_in(const fs::path& p, const toml::node& node, const std::string& key) {
  return p.string() + ":" + std::to_string(node.source().begin.line) + ": " + key + ": ";
}

/// Throws, naming file, line and key, when tab has a key outside known.
void require_known_keys(const fs::path& p, const toml::table& tab, const std::string& prefix,
                        const std::vector<std::string>& known) {
  for (const auto& [key, node] : tab) {
    const std::string name(key.str());
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    throw UserError(where_in(p, node, prefix + name) + "unknown key (expected one of " + list +
                    ")");
  }
}

/// The number at tab[key] (fallback when missing); throws, naming file, line and key, for
/// anything but a finite number >= 0 (written so that NaN fails).
double non_negative(const fs::path& p, const toml::table& tab, const std::string& key,
                    const std::string& prefix, double fallback) {
  const toml::node* node = tab.get(key);
  if (!node) return fallback;
  const std::optional<double> v = node->value<double>();
  if (!v || !std::isfinite(*v) || !(*v >= 0))
    throw UserError(where_in(p, *node, prefix + key) + "expected a finite number >= 0, got " +
                    describe(*node));
  return *v;
}

/// The array of strings at node; throws, naming file and key, for anything else.
std::vector<std::string> strings_at(const fs::path& p, toml::node_view<const toml::node> node,
                                    const std::string& where) {
  std::vector<std::string> out;
  const toml::array* a = node.as_array();
  if (!a) throw UserError(p.string() + ": " + where + ": expected an array of strings");
  for (const auto& v : *a) {
    if (!v.is_string()) throw UserError(where_in(p, v, where) + "expected an array of strings");
    out.push_back(v.value_or(std::string()));
  }
  return out;
}

/// An array of integrator names, parsed.
std::vector<cloth::Integrator> integrators_at(const fs::path& p,
                                              toml::node_view<const toml::node> node,
                                              const std::string& where) {
  std::vector<cloth::Integrator> out;
  const std::vector<std::string> names = strings_at(p, node, where);
  for (size_t k = 0; k < names.size(); ++k) {
    const auto i = cloth::parse_integrator(names[k]);
    if (!i)
      throw UserError(where_in(p, *node.as_array()->get(k), where) + "expected one of " +
                      join(integrator_names(), "\"") + ", got \"" + names[k] + "\"");
    out.push_back(*i);
  }
  return out;
}

/// [stability]: which searches to gate and how.
void read_stability_table(const fs::path& p, const toml::table& s, Tolerances& t) {
  require_known_keys(p, s, "stability.", {"engine", "integrators", "rel_tol", "adjacent"});
  t.stability = true;
  t.stability_engine = s["engine"].value_or(std::string());
  t.stability_rel_tol = non_negative(p, s, "rel_tol", "stability.", 0.02);
  if (!(t.stability_rel_tol > 0))
    throw UserError(where_in(p, *s.get("rel_tol"), "stability.rel_tol") + "expected a number > 0");
  t.stability_adjacent = s["adjacent"].value_or(false);
  if (s.contains("integrators"))
    t.stability_integrators = integrators_at(p, s["integrators"], "stability.integrators");
}

/// Whether q names a quantity a tolerance file may list: one of known, or a [test] metric,
/// test.<metric> (which metrics a scenario has, check knows).
bool known_quantity(const std::string& q, const std::vector<std::string>& known) {
  const bool test_metric = q.rfind("test.", 0) == 0 && q.size() > 5;
  return test_metric || std::find(known.begin(), known.end(), q) != known.end();
}

/// [ungated.<engine>]: quantities not gated for that engine, with the reason.
void read_ungated_table(const fs::path& p, const toml::table& u,
                        const std::vector<std::string>& known, Tolerances& t) {
  for (const auto& [engine_key, node] : u) {
    const std::string engine(engine_key.str()), where = "ungated." + engine;
    const toml::table* e = node.as_table();
    if (!e)
      throw UserError(where_in(p, node, where) +
                      "expected { quantities = [...], reason = \"...\" }");
    require_known_keys(p, *e, where + ".", {"quantities", "reason"});
    const std::string reason = (*e)["reason"].value_or(std::string());
    if (reason.empty()) throw UserError(p.string() + ": " + where + ": no reason");
    for (const std::string& q : strings_at(p, (*e)["quantities"], where + ".quantities")) {
      if (!known_quantity(q, known))
        throw UserError(p.string() + ": " + where + ": unknown quantity \"" + q + "\"");
      t.ungated[engine][q] = reason;
    }
  }
}

/// members = N of [ensemble.<engine>] (where): a whole number from 2 to 1000.
int fixed_members(const fs::path& p, const toml::node& members, const std::string& where) {
  const std::optional<int64_t> n = members.value_exact<int64_t>();
  if (!n || *n < 2 || *n > 1000)
    throw UserError(where_in(p, members, where + ".members") +
                    "expected a whole number from 2 to 1000, got " + describe(members));
  return int(*n);
}

/// detect = { quantity = shift, ... } of [ensemble.<engine>]: a shift > 0 for every quantity
/// of the ensemble and for no other.
void read_detect(const fs::path& p, const toml::node& node, const std::string& where,
                 Tolerances::Ensemble& ens) {
  const toml::table* d = node.as_table();
  if (!d)
    throw UserError(where_in(p, node, where + ".detect") +
                    "expected { quantity = shift, ... }, the shift of each quantity's mean "
                    "(in its unit) the gate must catch");
  for (const auto& [key, v] : *d) {
    const std::string q(key.str());
    if (!ens.quantities.count(q))
      throw UserError(where_in(p, v, where + ".detect." + q) +
                      "not one of the ensemble's quantities");
    const std::optional<double> x = v.value<double>();
    if (!x || !std::isfinite(*x) || !(*x > 0))
      throw UserError(where_in(p, v, where + ".detect." + q) +
                      "expected a finite shift > 0 in the quantity's unit, got " + describe(v));
    ens.detect[q] = *x;
  }
  for (const std::string& q : ens.quantities)
    if (!ens.detect.count(q))
      throw UserError(where_in(p, node, where + ".detect") + "no shift for \"" + q +
                      "\" (every quantity of the ensemble needs one)");
}

/// How many members: `members = N`, or chosen by `check --update` from the recorded spread
/// and `detect` within `max_seconds`.
void read_ensemble_size(const fs::path& p, const toml::table& e, const toml::node& node,
                        const std::string& where, Tolerances::Ensemble& ens) {
  const toml::node* members = e.get("members");
  const toml::node* detect = e.get("detect");
  if (members && detect)
    throw UserError(where_in(p, *members, where + ".members") +
                    "give members = N or detect = { ... }, not both (with detect, check "
                    "--update chooses N from the measured spread)");
  if (!members && !detect)
    throw UserError(where_in(p, node, where) +
                    "no members (expected members = N >= 2, or detect = { quantity = shift, "
                    "... } for an N chosen from the measured spread)");
  if (members) {
    if (e.get("max_seconds"))
      throw UserError(where_in(p, *e.get("max_seconds"), where + ".max_seconds") +
                      "only with detect (members = N is not chosen)");
    ens.members = fixed_members(p, *members, where);
    return;
  }
  read_detect(p, *detect, where, ens);
  ens.max_seconds = non_negative(p, e, "max_seconds", where + ".", ens.max_seconds);
  if (!(ens.max_seconds > 0))
    throw UserError(where_in(p, *e.get("max_seconds"), where + ".max_seconds") +
                    "expected a time > 0 (s)");
}

/// [ensemble.<engine>]: members (or how to choose them) and quantities gated by an ensemble,
/// with the reason.
void read_ensemble_table(const fs::path& p, const toml::table& u,
                         const std::vector<std::string>& known, Tolerances& t) {
  for (const auto& [engine_key, node] : u) {
    const std::string engine(engine_key.str()), where = "ensemble." + engine;
    const toml::table* e = node.as_table();
    if (!e)
      throw UserError(where_in(p, node, where) +
                      "expected { members = N, quantities = [...], reason = \"...\" }");
    require_known_keys(p, *e, where + ".",
                       {"members", "detect", "max_seconds", "quantities", "reason"});
    Tolerances::Ensemble& ens = t.ensemble[engine];
    ens.reason = (*e)["reason"].value_or(std::string());
    if (ens.reason.empty()) throw UserError(p.string() + ": " + where + ": no reason");
    for (const std::string& q : strings_at(p, (*e)["quantities"], where + ".quantities")) {
      if (!known_quantity(q, known))
        throw UserError(p.string() + ": " + where + ": unknown quantity \"" + q + "\"");
      const auto u_it = t.ungated.find(engine);
      if (u_it != t.ungated.end() && u_it->second.count(q))
        throw UserError(p.string() + ": " + where + ": \"" + q + "\" is also in [ungated." +
                        engine + "]; a quantity is gated by its ensemble or not at all");
      ens.quantities.insert(q);
    }
    if (ens.quantities.empty()) throw UserError(p.string() + ": " + where + ": no quantities");
    read_ensemble_size(p, *e, node, where, ens);
  }
}

/// [tests]: { abs, rel } per metric of tests.csv.
void read_tests_table(const fs::path& p, const toml::table& root, Tolerances& t) {
  const toml::table* tests = root["tests"].as_table();
  if (!tests)
    throw UserError(where_in(p, *root.get("tests"), "tests") +
                    "expected a table [tests] of metric = { abs = ..., rel = ... }");
  for (const auto& [key, node] : *tests) {
    const std::string name = "tests." + std::string(key.str());
    const toml::table* tab = node.as_table();
    if (!tab) throw UserError(where_in(p, node, name) + "expected { abs = ..., rel = ... }");
    require_known_keys(p, *tab, name + ".", {"abs", "rel"});
    t.tests[std::string(key.str())] = {non_negative(p, *tab, "abs", name + ".", 0.0),
                                       non_negative(p, *tab, "rel", name + ".", 0.0)};
  }
}

}  // namespace

Tolerances read_tolerances(const fs::path& p) {
  Tolerances t;
  const std::string text = read_tolerance_text(p);
  // a structurally extreme file would exhaust the parser's stack before it could complain
  if (const auto problem = toml_structure_problem(text))
    throw UserError(p.string() + ":" + std::to_string(problem->first) +
                    ": not a tolerance file: " + problem->second);
  toml::table root;
  try {
    root = toml::parse(text, p.string());
  } catch (const toml::parse_error& e) {
    throw UserError(p.string() + ":" + std::to_string(e.source().begin.line) + ": " +
                    std::string(e.description()));
  }
  std::vector<std::string> known = kMetricQuantities;
  known.push_back("final_shape_rms");
  for (const auto& [key, node] : root) {
    const std::string name(key.str());
    if (name == "stability" || name == "ungated" || name == "ensemble" || name == "mirror" ||
        name == "tests")
      continue;
    if (std::find(known.begin(), known.end(), name) == known.end())
      throw UserError(where_in(p, node, name) + "unknown quantity");
    const toml::table* tab = node.as_table();
    if (!tab) throw UserError(where_in(p, node, name) + "expected { abs = ..., rel = ... }");
    require_known_keys(p, *tab, name + ".", {"abs", "rel"});
    t.quantity[name] = {non_negative(p, *tab, "abs", name + ".", 0.0),
                        non_negative(p, *tab, "rel", name + ".", 0.0)};
  }
  for (const std::string& q : known)
    if (!t.quantity.count(q)) throw UserError(p.string() + ": no tolerance for " + q);
  if (const toml::table* s = root["stability"].as_table()) read_stability_table(p, *s, t);
  if (const toml::table* u = root["ungated"].as_table()) read_ungated_table(p, *u, known, t);
  if (root.contains("ensemble")) {
    const toml::table* e = root["ensemble"].as_table();
    if (!e)
      throw UserError(where_in(p, *root.get("ensemble"), "ensemble") +
                      "expected tables [ensemble.<engine>] with members = N (N >= 2)");
    read_ensemble_table(p, *e, known, t);
  }
  if (root.contains("tests")) read_tests_table(p, root, t);
  if (const toml::table* m = root["mirror"].as_table()) {
    require_known_keys(p, *m, "mirror.", {"engines"});
    for (const std::string& e : strings_at(p, (*m)["engines"], "mirror.engines"))
      t.mirrored.insert(e);
  }
  return t;
}

}  // namespace clothbench
