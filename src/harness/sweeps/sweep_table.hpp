#pragma once
/// @file sweep_table.hpp
/// A sweep's result file: appended and flushed row by row (so an interrupted sweep keeps its
/// finished rows), resumable, and rewritten in a fixed row order at the end (so the result
/// does not depend on the number of jobs or on completion order). It only writes text: the
/// sweeps keep their rows typed and hand it their fields.

#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "harness/io/csv_reader.hpp"

namespace clothbench {

/// A CSV table of sweep rows, each identified by its first key_columns fields.
class SweepTable {
 public:
  /// Opens path. With resume, rows already in the file (same header, as many fields) are kept
  /// and done() reports them; otherwise the file is started anew. Throws UserError naming the
  /// file when it cannot be written or its header differs, and the line of a second row with
  /// the same key.
  SweepTable(std::string path, std::vector<std::string> header, int key_columns, bool resume);
  ~SweepTable();
  SweepTable(const SweepTable&) = delete;
  SweepTable& operator=(const SweepTable&) = delete;

  /// The key of a row: its first key_columns fields joined by commas.
  std::string key(const std::vector<std::string>& fields) const;
  /// True when a row with this key is in the table.
  bool done(const std::string& key) const;
  /// The row with this key kept from the earlier sweep, as read (nullptr when none).
  const CsvRecord* kept(const std::string& key) const;
  /// Appends a row and flushes it to disk (thread-safe); throws UserError naming the file
  /// when it cannot be written (a full disk).
  void append(const std::vector<std::string>& fields);
  /// Rewrites the file with rows in the order of keys (rows with other keys after them).
  void finish(const std::vector<std::string>& key_order);

 private:
  void write_kept();
  void write_line(const std::string& line);

  std::string m_path;
  std::vector<std::string> m_header;
  int m_key_columns;
  std::vector<std::vector<std::string>> m_rows;
  std::map<std::string, size_t> m_index;
  std::map<std::string, CsvRecord> m_kept;
  std::FILE* m_file = nullptr;
  mutable std::mutex m_mutex;
};

}  // namespace clothbench
