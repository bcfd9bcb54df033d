/// @file cmd_schema.cpp
/// `clothbench schema`: the scenario file's keys and the output files' columns, as Markdown
/// tables built from the code's own definitions (docs/scenario-format.md and
/// docs/output-files.md include them verbatim; tests/docs/check_schema_docs.py compares).

#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/io/user_error.hpp"
#include "harness/scenario/scenario_schema.hpp"

namespace clothbench::cli {
namespace {

struct SchemaArgs {
  bool scenario = false;
  bool outputs = false;
  std::string format = "markdown";
};

int execute_schema(const SchemaArgs& a) {
  if (a.scenario == a.outputs) throw UserError("schema: expected one of --scenario or --outputs");
  if (a.scenario && a.format != "markdown")
    throw UserError("schema --scenario: --format " + a.format +
                    " is not offered; expected --format markdown");
  if (a.scenario)
    std::cout << scenario_schema_markdown();
  else
    std::cout << (a.format == "json" ? output_schema_json() : output_schema_markdown());
  return kExitOk;
}

}  // namespace

Command add_schema_command(CLI::App& app) {
  auto a = std::make_shared<SchemaArgs>();
  CLI::App* schema = app.add_subcommand(
      "schema",
      "Print the scenario file's keys (key, type, unit, default, range, meaning) or every\n"
      "output file's columns (column, unit, meaning) as Markdown tables, from the definitions\n"
      "the loader and the writers use.");
  schema->add_flag("--scenario", a->scenario, "every key of the scenario file, one table");
  schema->add_flag("--outputs", a->outputs, "every CSV file clothbench writes, one table each");
  schema->add_option("--format", a->format, "markdown, or json (with --outputs)")
      ->capture_default_str()
      ->check(CLI::IsMember({"markdown", "json"}));
  schema->footer(
      "Examples:\n"
      "  clothbench schema --scenario\n"
      "  clothbench schema --outputs --format json");
  return {schema, [a] { return execute_schema(*a); }};
}

}  // namespace clothbench::cli
