#include "harness/io/csv_writer.hpp"

#include <unistd.h>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "harness/io/user_error.hpp"

namespace clothbench {

std::string format_double(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  // the shortest of %.15g .. %.17g that reads back exactly
  char buf[40];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string csv_field(const std::string& f) {
  if (f.find_first_of(",\"\n") == std::string::npos) return f;
  std::string q = "\"";
  for (char ch : f) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

AtomicFile::AtomicFile(std::string path) : m_path(std::move(path)) {
  const std::filesystem::path p(m_path);
  m_tmp = (p.parent_path() / ("." + p.filename().string() + ".tmp." + std::to_string(::getpid())))
              .string();
  m_file = std::fopen(m_tmp.c_str(), "w");
  if (!m_file)
    throw UserError("cannot write in " + p.parent_path().string() + ": " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (m_file) {
    std::fclose(m_file);
    std::remove(m_tmp.c_str());
  }
}

void AtomicFile::write(const std::string& text) {
  if (std::fwrite(text.data(), 1, text.size(), m_file) != text.size())
    throw UserError("cannot write " + m_path + ": " + std::strerror(errno));
}

void AtomicFile::commit() {
  bool ok = std::fflush(m_file) == 0 && ::fsync(::fileno(m_file)) == 0;
  ok = std::fclose(m_file) == 0 && ok;
  m_file = nullptr;
  if (!ok || std::rename(m_tmp.c_str(), m_path.c_str()) != 0) {
    std::remove(m_tmp.c_str());
    throw UserError("cannot write " + m_path + ": " + std::strerror(errno));
  }
}

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& header)
    : m_file(path), m_columns(header.size()) {
  for (const std::string& h : header) add(h);
  end_row();
}

CsvWriter& CsvWriter::add(const std::string& field) {
  if (m_fields++ > 0) m_row += ',';
  m_row += field;
  return *this;
}

void CsvWriter::end_row() {
  if (m_fields != m_columns)
    throw std::logic_error(m_file.path() + ": row with " + std::to_string(m_fields) +
                           " fields for " + std::to_string(m_columns) + " columns");
  m_row += '\n';
  m_file.write(m_row);
  m_row.clear();
  m_fields = 0;
}

void make_directories(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw UserError("cannot create output folder " + dir + ": " +
                    (ec ? ec.message() : std::string("not a folder")));
  if (::access(dir.c_str(), W_OK) != 0)
    throw UserError("cannot write in output folder " + dir + ": " + std::strerror(errno));
}

}  // namespace clothbench
