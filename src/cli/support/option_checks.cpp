/// @file option_checks.cpp

#include "option_checks.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "harness/io/user_error.hpp"
#include "harness/scenario/scenario_format.hpp"
#include "reference/external/external_options.hpp"

namespace clothbench::cli {

CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(v) || !(v > 0))
          return "expected a finite number > 0, got \"" + text + "\"";
        return "";
      },
      "NUMBER > 0");
}

CLI::Validator positive_integer() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(text.c_str(), &end, 10);
        if (text.empty() || *end != '\0' || errno == ERANGE || v <= 0 || v > 1000000000)
          return "expected a whole number from 1 to 1e9, got \"" + text + "\"";
        return "";
      },
      "INTEGER > 0");
}

void add_max_run_seconds(CLI::App* sub, double& seconds) {
  sub->add_option("--max-run-seconds", seconds,
                  "wall-clock budget of each engine run (s): a run that takes longer stops and\n"
                  "counts as unstable with cause timeout (default: no limit)")
      ->check(positive_number());
}

void add_allow_external(CLI::App* sub) {
  sub->add_flag_callback(
      "--allow-external", [] { ::setenv(reference::kAllowExternalVariable, "1", 1); },
      "let engines of kind \"external\" start the programs their scenario names (the same as "
      "CLOTHBENCH_ALLOW_EXTERNAL=1 in the environment)");
}

void add_integrator_option(CLI::App* sub, std::vector<cloth::Integrator>& integrators,
                           const std::string& verb) {
  const std::string names = join(integrator_names());
  sub->add_option_function<std::vector<std::string>>(
         "--integrator,-i",
         [&integrators, names](const std::vector<std::string>& given) {
           integrators.clear();
           for (const std::string& name : given) {
             const auto i = cloth::parse_integrator(name);
             if (!i)
               throw UserError("--integrator " + name +
                               ": no such integrator (expected one of: " + names + ")");
             integrators.push_back(*i);
           }
         },
         "custom engines: " + verb + " only this integrator (repeatable; one of " + names +
             "; default: all " + std::to_string(cloth::all_integrators().size()) + ")")
      ->type_name("NAME")
      ->allow_extra_args(false);
}

void add_shard_option(CLI::App* sub, Shard& shard) {
  sub->add_option_function<std::string>(
         "--shard", [&shard](const std::string& text) { shard = parse_shard(text); },
         "compute only shard K of N of the sweep's rows (a fixed split: row i goes to shard\n"
         "i mod N + 1), for a cluster; give every shard its own --out, then `clothbench merge`")
      ->type_name("K/N");
}

void require_known_command(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return;  // options first: CLI11 says what is wrong
  const std::string word = argv[1];
  std::string known;
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_name() == word) return;
    known += (known.empty() ? "" : ", ") + sub->get_name();
  }
  throw UserError("unknown command \"" + word + "\"; the commands are " + known +
                  " (clothbench --help says what each does)");
}

void add_growth_options(CLI::App* sub, StabilityOptions& o) {
  sub->add_option_function<std::string>(
         "--method", [&o](const std::string& m) { o.method = parse_stability_method(m); },
         std::string(
             "blowup: the largest dt whose run over the scenario's duration stays finite;\n"
             "growth: the largest dt at which no small perturbation grows faster than its\n"
             "physical rate (measured in steps of dt / 8) plus --growth-tol, at a few states of\n"
             "a reference trajectory (the start, the fastest, the most contacts), without\n"
             "waiting for a blow-up; both: both column sets (default: ") +
             stability_method_name(o.method) + ")")
      ->check(CLI::IsMember({"blowup", "growth", "both"}));
  sub->add_option("--perturbation", o.perturbation,
                  "growth: finite-difference size, relative to the state's scale (positions\n"
                  "over the cloth's extent, velocities over extent / dt); from 1e-12 to 1e-3")
      ->capture_default_str();
  sub->add_option("--growth-tol", o.growth_tol,
                  "growth: a dt is unstable when a perturbation grows faster than the state's\n"
                  "physical rate by more than this (1/s; default ln 10: tenfold per second)")
      ->capture_default_str()
      ->check(positive_number());
}

}  // namespace clothbench::cli
