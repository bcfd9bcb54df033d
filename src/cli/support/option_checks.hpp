#pragma once
/// @file option_checks.hpp
/// Checks of command-line values with readable messages (CLI11's own ranges print their
/// bounds with 300 digits and let "nan" through).

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cloth/model/integrator.hpp"
#include "harness/stability/stability_sweep.hpp"
#include "harness/sweeps/shard.hpp"

namespace clothbench::cli {

/// A finite number > 0 ("nan", "inf", 0 and negatives are refused, naming the value).
CLI::Validator positive_number();

/// A whole number > 0.
CLI::Validator positive_integer();

/// Adds --max-run-seconds to sub, stored in seconds.
void add_max_run_seconds(CLI::App* sub, double& seconds);

/// Adds --allow-external to sub: given, it sets CLOTHBENCH_ALLOW_EXTERNAL=1 for this process,
/// which lets a scenario's kind = "external" engines start their programs.
void add_allow_external(CLI::App* sub);

/// Adds --integrator,-i to sub: repeatable, parsed into integrators (a name that is not an
/// integrator's is a UserError listing them); its help lists the names from cloth's own table.
void add_integrator_option(CLI::App* sub, std::vector<cloth::Integrator>& integrators,
                           const std::string& verb);

/// Adds --shard K/N to sub (a sweep's share for a cluster; shard.hpp), parsed into shard.
void add_shard_option(CLI::App* sub, Shard& shard);

/// --method, --perturbation and --growth-tol of a stability search (stability_sweep.hpp),
/// their defaults those of o.
void add_growth_options(CLI::App* sub, StabilityOptions& o);

/// Throws UserError when argv names a command the app does not have
/// (CLI11 alone says "A subcommand is required"): names it and lists the known ones.
void require_known_command(const CLI::App& app, int argc, char** argv);

}  // namespace clothbench::cli
