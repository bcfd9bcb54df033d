#include "fuzz_entries.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "harness/gate/tolerances_file.hpp"
#include "harness/io/csv_reader.hpp"
#include "harness/io/obj_reader.hpp"
#include "harness/io/user_error.hpp"
#include "harness/scenario/scenario_loader.hpp"

namespace clothbench::fuzz {

namespace {

std::string text_of(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// The input written to a scratch file of this process (the readers take a path), removed
/// when the entry is done: a test run leaves nothing in the temporary folder.
struct ScratchFile {
  std::string path;
  ScratchFile(const char* suffix, const std::uint8_t* data, std::size_t size)
      : path((std::filesystem::temp_directory_path() /
              ("clothbench-fuzz-" + std::to_string(::getpid()) + suffix))
                 .string()) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  ~ScratchFile() {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
};

}  // namespace

void scenario_text(const std::uint8_t* data, std::size_t size) {
  try {
    parse_scenario(text_of(data, size), "fuzz.toml");
  } catch (const UserError&) {
    // refused with a message: what a bad file must give
  }
}

void overrides(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> lines;
  std::istringstream in(text_of(data, size));
  for (std::string line; std::getline(in, line) && lines.size() < 8;) lines.push_back(line);
  try {
    parse_scenario(embedded_default_scenario(), "seed.toml", lines);
  } catch (const UserError&) {
  }
}

void csv_file(const std::uint8_t* data, std::size_t size) {
  const ScratchFile scratch(".csv", data, size);
  const std::string& path = scratch.path;
  try {
    const CsvTable table = read_csv_leniently(path);
    for (const CsvRecord& r : table.records)
      for (std::size_t c = 0; c < r.size(); ++c) {
        try {
          r.number(c, 0.0);
        } catch (const UserError&) {
        }
        try {
          r.integer(c);
        } catch (const UserError&) {
        }
      }
    if (!table.header.empty()) read_csv(path, table.header);
  } catch (const UserError&) {
  }
}

void tolerances_file(const std::uint8_t* data, std::size_t size) {
  const ScratchFile scratch(".toml", data, size);
  const std::string& path = scratch.path;
  try {
    const Tolerances t = read_tolerances(path);
    // what the reader accepts is usable: every tolerance a finite number >= 0
    for (const auto& [name, tol] : t.quantity)
      if (!(tol.abs >= 0 && tol.rel >= 0 && std::isfinite(tol.abs) && std::isfinite(tol.rel)))
        throw std::logic_error("tolerance " + name + " accepted but not a finite number >= 0");
    if (t.stability && !(t.stability_rel_tol > 0 && std::isfinite(t.stability_rel_tol)))
      throw std::logic_error("stability.rel_tol accepted but not a finite number > 0");
  } catch (const UserError&) {
  }
}

void obj_text(const std::uint8_t* data, std::size_t size) {
  try {
    const ObjFile f = read_obj_text(text_of(data, size), "fuzz.obj");
    // what the reader accepts is usable: indices in range, a line for everything
    const int nv = f.mesh.vertex_count();
    for (const auto& t : f.mesh.triangles)
      for (int v : t)
        if (v < 0 || v >= nv) throw std::logic_error("accepted a triangle with a bad index");
    if (f.vertex_line.size() != static_cast<std::size_t>(nv) ||
        f.triangle_line.size() != f.mesh.triangles.size())
      throw std::logic_error("accepted a mesh without a line per vertex and triangle");
    if (!f.mesh.x.allFinite()) throw std::logic_error("accepted a coordinate that is not finite");
  } catch (const UserError&) {
  }
}

const std::vector<std::pair<std::string, Entry>>& entries() {
  static const std::vector<std::pair<std::string, Entry>> all = {{"scenario", scenario_text},
                                                                 {"overrides", overrides},
                                                                 {"csv", csv_file},
                                                                 {"tolerances", tolerances_file},
                                                                 {"obj", obj_text}};
  return all;
}

}  // namespace clothbench::fuzz
