#pragma once
/// @file scenario_input.hpp
/// The scenarios a command line names: a file, the embedded seed scene, or every shipped one.

#include <string>
#include <vector>

#include "harness/scenario/scenario.hpp"

namespace clothbench::cli {

/// The scenario at path (the embedded seed scene when path is empty), keeping the engines named
/// in only (and the reference), so an engine left out need not be able to model an overridden
/// scene. Throws ScenarioError (a UserError) for a bad file or override.
Scenario load_or_seed(const std::string& path, const std::vector<std::string>& overrides,
                      const std::vector<std::string>& only);

/// Throws UserError when the file out_dir/written, which a command is about to write, is the
/// scenario file it reads (`run SCEN -o DIR` with DIR/scenario.toml being SCEN): an input is
/// never overwritten.
void refuse_overwriting_input(const std::string& scenario_path, const std::string& out_dir,
                              const std::string& written);

/// Every shipped scenario file (scenarios/**/*.toml of the source tree), sorted.
std::vector<std::string> shipped_scenarios();

}  // namespace clothbench::cli
