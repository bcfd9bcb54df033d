/// @file scenario_input.cpp

#include "scenario_input.hpp"

#include <algorithm>
#include <filesystem>

#include "harness/scenario_loader.hpp"

namespace clothbench::cli {

Scenario load_or_seed(const std::string& path, const std::vector<std::string>& overrides,
                      const std::vector<std::string>& only) {
  if (path.empty())
    return parse_scenario(embedded_default_scenario(), "<embedded seed_sphere_drape>", overrides,
                          only);
  return load_scenario(path, overrides, only);
}

std::vector<std::string> shipped_scenarios() {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(CLOTHBENCH_SCENARIO_DIR))
    if (e.path().extension() == ".toml") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace clothbench::cli
