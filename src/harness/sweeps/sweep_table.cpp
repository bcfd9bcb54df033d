#include "harness/sweeps/sweep_table.hpp"

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "harness/io/csv_writer.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench {

namespace {

std::string join(const std::vector<std::string>& fields, size_t count) {
  std::string s;
  for (size_t i = 0; i < count && i < fields.size(); ++i)
    s += (i ? "," : "") + csv_field(fields[i]);
  return s;
}

}  // namespace

SweepTable::SweepTable(std::string path, std::vector<std::string> header, int key_columns,
                       bool resume)
    : m_path(std::move(path)), m_header(std::move(header)), m_key_columns(key_columns) {
  if (resume) {
    const CsvTable earlier = read_csv_leniently(m_path);
    if (!earlier.header.empty() && earlier.header != m_header)
      throw UserError(m_path + ": cannot resume: its header is not " +
                      join(m_header, m_header.size()));
    for (const CsvRecord& r : earlier.records) {
      if (r.size() != m_header.size()) continue;  // not a row of this table
      if (m_index.count(key(r.fields())))
        throw UserError(m_path + ":" + std::to_string(r.line()) +
                        ": cannot resume: a second row for " + key(r.fields()) +
                        " (each configuration has one row); remove one of them "
                        "or run without --resume");
      m_index[key(r.fields())] = m_rows.size();
      m_rows.push_back(r.fields());
      m_kept.insert_or_assign(key(r.fields()), r);
    }
  }
  write_kept();
}

SweepTable::~SweepTable() {
  if (m_file) std::fclose(m_file);
}

void SweepTable::write_kept() {
  // rewrite what was kept (drops a partial last line), then append from there
  m_file = std::fopen(m_path.c_str(), "w");
  if (!m_file) throw UserError("cannot write " + m_path + ": " + std::strerror(errno));
  write_line(join(m_header, m_header.size()));
  for (const auto& r : m_rows) write_line(join(r, r.size()));
}

void SweepTable::write_line(const std::string& line) {
  // a row counts as kept only once it is on disk: a full disk fails the sweep, naming the file
  if (std::fprintf(m_file, "%s\n", line.c_str()) < 0 || std::fflush(m_file) != 0)
    throw UserError("cannot write " + m_path + ": " + std::strerror(errno));
}

std::string SweepTable::key(const std::vector<std::string>& fields) const {
  return join(fields, static_cast<size_t>(m_key_columns));
}

bool SweepTable::done(const std::string& k) const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return m_index.count(k) > 0;
}

const CsvRecord* SweepTable::kept(const std::string& k) const {
  std::lock_guard<std::mutex> lock(m_mutex);
  const auto it = m_kept.find(k);
  return it == m_kept.end() ? nullptr : &it->second;
}

void SweepTable::append(const std::vector<std::string>& fields) {
  if (fields.size() != m_header.size())
    throw std::logic_error(m_path + ": row of " + std::to_string(fields.size()) + " fields");
  std::lock_guard<std::mutex> lock(m_mutex);
  m_index[key(fields)] = m_rows.size();
  m_rows.push_back(fields);
  write_line(join(fields, fields.size()));
}

void SweepTable::finish(const std::vector<std::string>& key_order) {
  std::lock_guard<std::mutex> lock(m_mutex);
  std::fclose(m_file);
  m_file = nullptr;
  std::vector<std::vector<std::string>> ordered;
  std::vector<bool> used(m_rows.size(), false);
  for (const std::string& k : key_order) {
    auto it = m_index.find(k);
    if (it == m_index.end() || used[it->second]) continue;
    used[it->second] = true;
    ordered.push_back(m_rows[it->second]);
  }
  for (size_t i = 0; i < m_rows.size(); ++i)
    if (!used[i]) ordered.push_back(m_rows[i]);
  AtomicFile out(m_path);
  out.write(join(m_header, m_header.size()) + "\n");
  for (const auto& r : ordered) out.write(join(r, r.size()) + "\n");
  out.commit();
  m_rows = std::move(ordered);
  m_index.clear();
  for (size_t i = 0; i < m_rows.size(); ++i) m_index[key(m_rows[i])] = i;
}

}  // namespace clothbench
