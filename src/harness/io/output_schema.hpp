#pragma once
/// @file output_schema.hpp
/// Every CSV file clothbench writes, with its columns in order, their units and meanings: the
/// one definition the writers take their headers from, the readers their expected columns,
/// `clothbench schema --outputs` its tables and the analysis' column check its names.

#include <string>
#include <string_view>
#include <vector>

namespace clothbench {

/// One column of an output file.
struct OutputColumn {
  const char* name;
  const char* unit;     // SI: m, s, J, kg, N, m^2, 1 (dimensionless), count; text; 0/1 (a flag)
  const char* meaning;  // one sentence
};

/// One CSV file: where it is written, what a row is, and its columns in order.
struct OutputFile {
  const char* name;        // "frames.csv"; "baselines/metrics.csv" for a baseline's files
  const char* written_by;  // the command that writes it and where
  const char* row;         // what one row is
  std::vector<OutputColumn> columns;
};

/// The name of map.csv's leading columns: one per --vary key, named by the key.
inline constexpr const char* kVariedKeyColumn = "<varied key>";

/// Every output file, in the order `clothbench schema --outputs` prints them.
const std::vector<OutputFile>& output_files();
/// The file of that name; throws std::logic_error for a name not in output_files().
const OutputFile& output_file(std::string_view name);
/// The column names of that file, in order (map.csv: the fixed columns after the varied keys).
std::vector<std::string> output_header(std::string_view name);

/// text for a Markdown table cell: '|' escaped as "\|".
std::string markdown_cell(std::string_view text);

/// One Markdown table per file (column, unit, meaning), each under a "### name" heading.
std::string output_schema_markdown();
/// {"files": [{"name": ..., "written_by": ..., "row": ..., "columns": [{"name", "unit",
/// "meaning"}, ...]}, ...]}: the same data for programs (the analysis' column check).
std::string output_schema_json();

}  // namespace clothbench
