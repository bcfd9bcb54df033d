#pragma once
/// @file scenario_error.hpp
/// The error of a scenario the user got wrong, located at the file and line or the --set
/// override:
///   scenarios/x.toml:12: cloth.damping: expected a number >= 0, got -3
///   --set engine.custom-rk4.dt: expected a number > 0, got -1

#include <string>

#include "harness/io/user_error.hpp"

namespace clothbench {

/// A scenario the user got wrong: bad file, bad key, bad value, bad override.
class ScenarioError : public UserError {
 public:
  /// @param where    "file:line", "--set key" or a file name alone (unreadable file)
  /// @param key      dotted key path ("cloth.damping", "engine.custom-rk4.dt"); may be empty
  /// @param problem  what was expected and what was found
  ScenarioError(const std::string& where, const std::string& key, const std::string& problem)
      : UserError(where + ": " + (key.empty() ? "" : key + ": ") + problem),
        m_where(where),
        m_key(key),
        m_problem(problem) {}

  const std::string& where() const { return m_where; }
  const std::string& key() const { return m_key; }
  const std::string& problem() const { return m_problem; }

 private:
  std::string m_where, m_key, m_problem;
};

}  // namespace clothbench
