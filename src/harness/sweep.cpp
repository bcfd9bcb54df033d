#include "harness/sweep.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <exception>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "harness/csv_writer.hpp"

namespace clothbench {

int default_jobs() {
  return std::max(1u, std::thread::hardware_concurrency());
}

void run_parallel(int n, int jobs, const std::function<void(int)>& work) {
  std::atomic<int> next{0};
  std::exception_ptr first_error;
  std::mutex error_mutex;
  auto worker = [&]() {
    for (int i = next++; i < n; i = next++) {
      try {
        work(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!first_error) first_error = std::current_exception();
        next = n;  // no new jobs
      }
    }
  };
  const int threads = std::max(1, std::min(jobs, n));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

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

std::string csv_field(const std::string& f) {
  if (f.find_first_of(",\"\n") == std::string::npos) return f;
  std::string q = "\"";
  for (char ch : f) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

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
    std::ifstream file(m_path);
    std::stringstream text;
    text << file.rdbuf();
    std::string all = text.str();
    // a last line without its newline was cut short by an interruption: drop it
    if (!all.empty() && all.back() != '\n') all.erase(all.find_last_of('\n') + 1);
    std::istringstream in(all);
    std::string line;
    if (std::getline(in, line)) {
      if (split_csv_line(line) != m_header)
        throw std::runtime_error(m_path + ": cannot resume: its header is not " +
                                 join(m_header, m_header.size()));
      while (std::getline(in, line)) {
        std::vector<std::string> f = split_csv_line(line);
        if (f.size() != m_header.size()) continue;  // not a row of this table
        m_index[key(f)] = m_rows.size();
        m_rows.push_back(std::move(f));
      }
    }
  }
  // rewrite what was kept (drops a partial last line), then append from there
  m_file = std::fopen(m_path.c_str(), "w");
  if (!m_file) throw std::runtime_error("cannot write " + m_path + ": " + std::strerror(errno));
  std::fprintf(m_file, "%s\n", join(m_header, m_header.size()).c_str());
  for (const auto& r : m_rows) std::fprintf(m_file, "%s\n", join(r, r.size()).c_str());
  std::fflush(m_file);
}

SweepTable::~SweepTable() {
  if (m_file) std::fclose(m_file);
}

std::string SweepTable::key(const std::vector<std::string>& fields) const {
  return join(fields, static_cast<size_t>(m_key_columns));
}

bool SweepTable::done(const std::string& k) const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return m_index.count(k) > 0;
}

std::vector<std::string> SweepTable::row(const std::string& k) const {
  std::lock_guard<std::mutex> lock(m_mutex);
  auto it = m_index.find(k);
  return it == m_index.end() ? std::vector<std::string>{} : m_rows[it->second];
}

std::vector<std::vector<std::string>> SweepTable::rows() const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return m_rows;
}

void SweepTable::append(const std::vector<std::string>& fields) {
  if (fields.size() != m_header.size())
    throw std::logic_error(m_path + ": row of " + std::to_string(fields.size()) + " fields");
  std::lock_guard<std::mutex> lock(m_mutex);
  m_index[key(fields)] = m_rows.size();
  m_rows.push_back(fields);
  std::fprintf(m_file, "%s\n", join(fields, fields.size()).c_str());
  std::fflush(m_file);
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

EngineSpec with_integrator_and_dt(const EngineSpec& e, const std::string& integrator, double dt) {
  EngineSpec out = e;
  out.dt = dt;
  if (e.kind == EngineKind::custom && !integrator.empty()) {
    const auto i = cloth::parse_integrator(integrator);
    if (!i) throw std::invalid_argument("unknown integrator " + integrator);
    out.solver.integrator = *i;
  }
  return out;
}

std::string rerun_overrides(const EngineSpec& e) {
  std::string s;
  if (e.kind == EngineKind::custom)
    s += "--set engine." + e.name + ".integrator=" + cloth::integrator_name(e.solver.integrator) +
         " ";
  s += "--set engine." + e.name + ".dt=" + format_double(e.dt);
  return s;
}

}  // namespace clothbench
