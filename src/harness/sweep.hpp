#pragma once
/// @file sweep.hpp
/// What every sweep shares: independent runs spread over threads, and a result table that is
/// appended and flushed row by row (so an interrupted sweep keeps its finished rows), can be
/// resumed, and is rewritten in a fixed row order at the end (so the result does not depend on
/// the number of jobs or on completion order).

#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "harness/scenario.hpp"

namespace clothbench {

/// Number of jobs when the user gives none: every core.
int default_jobs();

/// Runs work(i) for every i in [0, n) on up to jobs threads. An exception in any job stops
/// the remaining ones and is rethrown (the first one) after all threads finish.
void run_parallel(int n, int jobs, const std::function<void(int)>& work);

/// A CSV table of sweep rows, each identified by its first key_columns fields.
class SweepTable {
 public:
  /// Opens path. With resume, rows already in the file (same header) are kept and done()
  /// reports them; otherwise the file is started anew. Throws std::runtime_error naming the
  /// file when it cannot be written or its header differs.
  SweepTable(std::string path, std::vector<std::string> header, int key_columns, bool resume);
  ~SweepTable();
  SweepTable(const SweepTable&) = delete;
  SweepTable& operator=(const SweepTable&) = delete;

  /// The key of a row: its first key_columns fields joined by commas.
  std::string key(const std::vector<std::string>& fields) const;
  /// True when a row with this key is in the table.
  bool done(const std::string& key) const;
  /// The stored row with this key (empty when none).
  std::vector<std::string> row(const std::string& key) const;
  /// Appends a row and flushes it to disk (thread-safe).
  void append(const std::vector<std::string>& fields);
  /// Rewrites the file with rows in the order of keys (rows with other keys after them).
  void finish(const std::vector<std::string>& key_order);
  /// All rows, in file order.
  std::vector<std::vector<std::string>> rows() const;

 private:
  std::string m_path;
  std::vector<std::string> m_header;
  int m_key_columns;
  std::vector<std::vector<std::string>> m_rows;
  std::map<std::string, size_t> m_index;
  std::FILE* m_file = nullptr;
  mutable std::mutex m_mutex;
};

/// One custom-engine configuration of a sweep: the engine of a scenario with its integrator
/// (custom engines only) and dt replaced.
EngineSpec with_integrator_and_dt(const EngineSpec& e, const std::string& integrator, double dt);

/// The --set overrides that make `clothbench run` repeat a sweep row on the scenario file.
std::string rerun_overrides(const EngineSpec& e);

/// The whole text of the file at path ("" when it cannot be read).
std::string read_text(const std::string& path);

/// Splits a CSV line; a field in double quotes may hold commas ("" is a quote).
std::vector<std::string> split_csv_line(const std::string& line);

/// A field as written to CSV: quoted when it holds a comma, a quote or a newline.
std::string csv_field(const std::string& field);

}  // namespace clothbench
