/// @file cmd_list.cpp
/// `clothbench list`: the shipped scenarios, engine kinds and integrators.

#include <exception>
#include <filesystem>
#include <iostream>
#include <string>

#include "cloth/model/integrator.hpp"
#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/scenario/engine_kind.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "support/scenario_input.hpp"

namespace clothbench::cli {
namespace {

int execute_list() {
  std::cout << "scenarios (" << CLOTHBENCH_SCENARIO_DIR << "):\n";
  for (const std::filesystem::path f : shipped_scenarios()) {
    // a scenario that does not load is listed with the reason, not fatal
    try {
      const Scenario sc = load_scenario(f.string());
      const std::string cloth =
          sc.scene.mesh
              ? std::to_string(sc.scene.particle_count()) + "-vertex mesh"
              : std::to_string(sc.scene.cloth.nu) + "x" + std::to_string(sc.scene.cloth.nv);
      std::cout << "  " << sc.name << "  " << cloth << ", " << sc.engines.size()
                << " engines: " << sc.description << '\n';
    } catch (const std::exception& e) {
      std::cout << "  " << f.filename().string() << "  (does not load: " << e.what() << ")\n";
    }
  }
  std::cout << "engine kinds:";
  for (const EngineKindInfo& k : engine_kind_table()) std::cout << ' ' << k.name;
  std::cout << "\nintegrators (kind = \"custom\"):";
  for (cloth::Integrator i : cloth::all_integrators())
    std::cout << ' ' << cloth::integrator_name(i);
  std::cout << '\n';
  return kExitOk;
}

}  // namespace

Command add_list_command(CLI::App& app) {
  CLI::App* list =
      app.add_subcommand("list", "List the shipped scenarios, engine kinds and integrators.");
  return {list, [] { return execute_list(); }};
}

}  // namespace clothbench::cli
