#pragma once
/// @file csv_reader.hpp
/// The one way clothbench reads a CSV file back (a sweep's rows to resume, a recorded
/// baseline): lines split into fields, and typed access to a field whose errors name the
/// file, the line, the column and what was expected, thrown as UserError.

#include <memory>
#include <string>
#include <vector>

namespace clothbench {

/// Splits a CSV line; a field in double quotes may hold commas ("" is a quote).
std::vector<std::string> split_csv_line(const std::string& line);

/// One data line of a CSV file: its fields, and where it came from for error messages.
class CsvRecord {
 public:
  /// Where a record came from: the file and its column names (shared by its records).
  struct Source {
    std::string path;
    std::vector<std::string> header;
  };

  CsvRecord(std::shared_ptr<const Source> source, int line, std::vector<std::string> fields);

  const std::vector<std::string>& fields() const { return m_fields; }
  size_t size() const { return m_fields.size(); }
  /// 1-based line number in the file.
  int line() const { return m_line; }

  /// The field of column as written.
  const std::string& text(size_t column) const;
  /// The field of column as a number ("nan", "inf" allowed); empty gives if_empty.
  /// Throws UserError naming file, line and column when it is not a number.
  double number(size_t column, double if_empty) const;
  /// The field of column as a whole number; throws UserError when it is not one.
  long long integer(size_t column) const;
  /// Throws UserError "PATH:LINE: COLUMN: expected EXPECTED, got "FIELD"".
  [[noreturn]] void fail(size_t column, const std::string& expected) const;

 private:
  std::string column_name(size_t column) const;

  std::shared_ptr<const Source> m_source;
  int m_line;
  std::vector<std::string> m_fields;
};

/// A CSV file as read: its header line and its data lines.
struct CsvTable {
  std::string path;
  std::vector<std::string> header;  // empty for an empty or missing file (lenient reading)
  std::vector<CsvRecord> records;   // in file order, blank lines left out
};

/// Reads a CSV file that must exist, start with exactly header and have header.size() fields
/// on every non-blank line. Throws UserError naming the file (and line) otherwise.
CsvTable read_csv(const std::string& path, const std::vector<std::string>& header);

/// Reads what an earlier, possibly interrupted, sweep left: no file or an empty one gives an
/// empty table, a last line without its newline (cut short) is dropped, the header is taken as
/// found and rows of any field count are kept (the caller picks its own).
CsvTable read_csv_leniently(const std::string& path);

}  // namespace clothbench
