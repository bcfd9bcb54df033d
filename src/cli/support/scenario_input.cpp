/// @file scenario_input.cpp

#include "scenario_input.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "harness/io/user_error.hpp"
#include "harness/scenario/scenario_loader.hpp"

namespace clothbench::cli {

Scenario load_or_seed(const std::string& path, const std::vector<std::string>& overrides,
                      const std::vector<std::string>& only) {
  if (path.empty())
    return parse_scenario(embedded_default_scenario(), "<embedded seed_sphere_drape>", overrides,
                          only);
  Scenario sc = load_scenario(path, overrides, only);
  // what loading accepted but a user should know (an unused mesh vertex)
  for (const std::string& w : sc.warnings) std::cerr << "clothbench: warning: " << w << '\n';
  return sc;
}

void refuse_overwriting_input(const std::string& scenario_path, const std::string& out_dir,
                              const std::string& written) {
  std::error_code ec;
  const std::string target = out_dir + "/" + written;
  if (scenario_path.empty() || !std::filesystem::equivalent(scenario_path, target, ec) || ec)
    return;
  throw UserError(target + " is the scenario file " + scenario_path +
                  " itself, which this command would overwrite; choose another output folder "
                  "(--out)");
}

std::vector<std::string> shipped_scenarios() {
  std::vector<std::string> files;
  // scenarios/**/*.toml; the meshes they read live in scenarios/meshes/ and are not scenarios
  for (const auto& e : std::filesystem::recursive_directory_iterator(CLOTHBENCH_SCENARIO_DIR))
    if (e.is_regular_file() && e.path().extension() == ".toml") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace clothbench::cli
