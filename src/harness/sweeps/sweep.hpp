#pragma once
/// @file sweep.hpp
/// One configuration of a sweep: an engine of a scenario with its integrator and dt replaced,
/// and the command-line overrides that repeat it with `clothbench run`.

#include <optional>
#include <string>

#include "cloth/model/integrator.hpp"
#include "harness/scenario/scenario.hpp"

namespace clothbench {

/// One configuration of a sweep: the engine of a scenario with its dt replaced and, for a
/// custom engine given one, its integrator; its label (progress lines) says which:
/// "NAME (INTEGRATOR, dt = DT s)", the integrator only when it changed.
EngineSpec with_integrator_and_dt(const EngineSpec& e, std::optional<cloth::Integrator> integrator,
                                  double dt);

/// The integrator as a sweep's rows and row keys name it: its name, "" for none (a Bullet
/// engine).
std::string integrator_label(std::optional<cloth::Integrator> integrator);

/// The line a sweep's record gives its wall-clock budget (--max-run-seconds, never a scenario
/// key), so that --resume and merge keep to one budget: "" when sc has none, else a TOML
/// comment line ending in a newline.
std::string budget_line(const Scenario& sc);

/// The --set overrides that make `clothbench run` repeat a sweep row on the scenario file.
std::string rerun_overrides(const EngineSpec& e);

}  // namespace clothbench
