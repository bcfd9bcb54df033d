#pragma once
/// @file external_options.hpp
/// Options of an external engine: a program the harness starts and speaks the protocol of
/// docs/external-engines.md with (external_engine.hpp).

#include <string>
#include <vector>

namespace clothbench::reference {

/// The environment variable that allows external engines as --allow-external does.
constexpr const char* kAllowExternalVariable = "CLOTHBENCH_ALLOW_EXTERNAL";

/// Options of kind = "external".
struct ExternalOptions {
  /// The program and its arguments, run without a shell (arguments naming files relative to the
  /// scenario file's folder already resolved by the loader).
  std::vector<std::string> command;
  double step_timeout = 60.0;  // s of wall clock the engine has to answer one request
  /// The run's thread and the engine's process on one CPU for the engine's life (cpu_pin.hpp):
  /// the protocol is a strict alternation, so one CPU loses no parallelism and the hand-overs
  /// stay on it. For single-threaded engines: a multi-threaded one would share that one CPU.
  bool share_cpu = false;
};

/// True when CLOTHBENCH_ALLOW_EXTERNAL=1 is set (the CLI's --allow-external sets it).
bool external_allowed();

/// What a user must do to run a scenario whose engine name runs an external program.
std::string external_not_allowed_message(const std::string& engine_name);

}  // namespace clothbench::reference
