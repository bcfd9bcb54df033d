#include "harness/io/csv_reader.hpp"

#include <cerrno>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "harness/io/text_file.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench {

namespace {

std::string joined(const std::vector<std::string>& fields) {
  std::string s;
  for (const std::string& f : fields) s += (s.empty() ? "" : ",") + f;
  return s;
}

/// The records of text after its header line; blank lines are left out.
CsvTable split_table(const std::string& path, const std::string& text) {
  CsvTable table;
  table.path = path;
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line)) return table;
  table.header = split_csv_line(line);
  const auto source =
      std::make_shared<const CsvRecord::Source>(CsvRecord::Source{path, table.header});
  for (int number = 2; std::getline(in, line); ++number)
    if (!line.empty()) table.records.emplace_back(source, number, split_csv_line(line));
  return table;
}

}  // namespace

std::vector<std::string> split_csv_line(const std::string& line) {
  // RFC 4180 quoting: a field in double quotes may hold commas and doubled quotes
  std::vector<std::string> out;
  std::string field;
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted) {
      if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        field += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      out.push_back(std::move(field));
      field.clear();
    } else {
      field += ch;
    }
  }
  out.push_back(std::move(field));
  return out;
}

CsvRecord::CsvRecord(std::shared_ptr<const Source> source, int line,
                     std::vector<std::string> fields)
    : m_source(std::move(source)), m_line(line), m_fields(std::move(fields)) {}

const std::string& CsvRecord::text(size_t column) const {
  if (column >= m_fields.size()) fail(column, "a field");
  return m_fields[column];
}

double CsvRecord::number(size_t column, double if_empty) const {
  const std::string& f = text(column);
  if (f.empty()) return if_empty;
  char* end = nullptr;
  const double v = std::strtod(f.c_str(), &end);
  if (end != f.c_str() + f.size()) fail(column, "a number");
  return v;
}

long long CsvRecord::integer(size_t column) const {
  const std::string& f = text(column);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(f.c_str(), &end, 10);
  if (f.empty() || end != f.c_str() + f.size() || errno == ERANGE) fail(column, "a whole number");
  return v;
}

void CsvRecord::fail(size_t column, const std::string& expected) const {
  const std::string got =
      column < m_fields.size() ? "\"" + m_fields[column] + "\"" : std::string("no such field");
  throw UserError(m_source->path + ":" + std::to_string(m_line) + ": " + column_name(column) +
                  ": expected " + expected + ", got " + got);
}

std::string CsvRecord::column_name(size_t column) const {
  const std::vector<std::string>& h = m_source->header;
  return column < h.size() ? h[column] : "column " + std::to_string(column + 1);
}

CsvTable read_csv(const std::string& path, const std::vector<std::string>& header) {
  CsvTable table = split_table(path, read_existing_text(path));
  if (table.header != header)
    throw UserError(path + ":1: expected the header " + joined(header) + ", got " +
                    (table.header.empty() ? std::string("an empty file") : joined(table.header)));
  for (const CsvRecord& r : table.records)
    if (r.size() != header.size())
      throw UserError(path + ":" + std::to_string(r.line()) + ": expected " +
                      std::to_string(header.size()) + " fields (" + joined(header) + "), got " +
                      std::to_string(r.size()));
  return table;
}

CsvTable read_csv_leniently(const std::string& path) {
  std::string text = read_text(path);
  // a last line without its newline was cut short by an interruption: drop it
  if (!text.empty() && text.back() != '\n') text.erase(text.find_last_of('\n') + 1);
  return split_table(path, text);
}

}  // namespace clothbench
