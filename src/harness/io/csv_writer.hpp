#pragma once
/// @file csv_writer.hpp
/// CSV output written atomically: rows go to a hidden temporary file beside the target, which
/// replaces the target only on commit(), so an interrupted run leaves no half-written CSV.

#include <cstdio>
#include <string>
#include <vector>

namespace clothbench {

/// Shortest text that reads back as the same double ("nan", "inf" and "-inf" for non-finite).
std::string format_double(double v);

/// A field as written to CSV: quoted when it holds a comma, a quote or a newline.
std::string csv_field(const std::string& field);

/// A file that appears under its name only when committed.
class AtomicFile {
 public:
  /// Opens a temporary file beside path. Throws UserError naming the folder when it
  /// cannot be written.
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const std::string& text);
  /// Flushes, closes and renames the temporary file onto the target.
  void commit();
  const std::string& path() const { return m_path; }

 private:
  std::string m_path, m_tmp;
  std::FILE* m_file = nullptr;
};

/// A CSV table: a header, then rows of fields, written atomically.
class CsvWriter {
 public:
  CsvWriter(const std::string& path, const std::vector<std::string>& header);
  /// Starts a row; fields follow with add(); end_row() writes it.
  CsvWriter& add(const std::string& field);
  CsvWriter& add(double v) { return add(format_double(v)); }
  CsvWriter& add(long long v) { return add(std::to_string(v)); }
  CsvWriter& add(int v) { return add(std::to_string(v)); }
  /// An empty field.
  CsvWriter& skip() { return add(std::string()); }
  void end_row();
  void commit() { m_file.commit(); }

 private:
  AtomicFile m_file;
  size_t m_columns;
  std::string m_row;
  size_t m_fields = 0;
};

/// Creates a folder and its parents; throws UserError naming it when that fails.
void make_directories(const std::string& dir);

}  // namespace clothbench
