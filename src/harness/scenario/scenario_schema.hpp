#pragma once
/// @file scenario_schema.hpp
/// Every key a scenario file may have, with its type, unit, default, range and meaning: built
/// from the loader's own key lists (scenario_format.hpp), the option structs' in-class defaults
/// and the loader's bounds, and printed by `clothbench schema --scenario`.

#include <string>
#include <vector>

namespace clothbench {

struct Bound;

/// One key of the scenario file.
struct ScenarioKey {
  std::string table;  // "" at the top, "cloth", "cloth.stiffness", "sphere" ([[sphere]]), ...
  std::string key;    // the key within its table
  std::string kind;   // an [[engine]] key of one engine kind only: that kind; "" otherwise
  std::string type;   // "number", "integer", "string", "boolean", "[x, y, z]", "table", ...
  std::string unit;   // SI unit, "1" for dimensionless, "" when not a quantity
  std::string default_value;  // what a file that leaves the key out gets
  std::string range;          // what the loader accepts ("> 0", "one of ...")
  std::string meaning;        // one sentence
  // the range the loader checks, for the test that both agree: a number's bound, or an
  // integer's least and greatest value (int_max when unbounded above)
  const Bound* bound = nullptr;
  bool integer = false;
  long long min = 0, max = 0;

  /// The dotted path as a user writes it: "cloth.particles", "engine.dt".
  std::string path() const { return table.empty() ? key : table + "." + key; }
};

/// Every key, in the order `clothbench schema --scenario` prints them.
const std::vector<ScenarioKey>& scenario_keys();
/// The Markdown table: key, type, unit, default, range, meaning.
std::string scenario_schema_markdown();

}  // namespace clothbench
