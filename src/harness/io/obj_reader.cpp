#include "harness/io/obj_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string_view>
#include <unordered_map>

#include "cloth/model/mesh_check.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench {

namespace {

/// Problems named in one error message before "and N more".
constexpr int kProblemsShown = 5;

/// Keywords read as nothing, silently: texture, normals, smoothing and materials.
bool silently_ignored(std::string_view k) {
  return k == "vt" || k == "vn" || k == "s" || k == "usemtl" || k == "mtllib";
}

/// Keywords of the format that describe no triangles: ignored with a warning.
bool ignored_with_warning(std::string_view k) {
  static const char* const kinds[] = {
      "vp",         "l",         "p",     "cstype", "deg",   "bmat",     "step",
      "curv",       "curv2",     "surf",  "parm",   "trim",  "hole",     "scrv",
      "sp",         "end",       "con",   "mg",     "lod",   "usemap",   "maplib",
      "shadow_obj", "trace_obj", "ctech", "stech",  "bevel", "c_interp", "d_interp"};
  return std::any_of(std::begin(kinds), std::end(kinds), [&](const char* s) { return k == s; });
}

/// The next whitespace-separated token of rest (empty at the end), removed from rest.
std::string_view next_token(std::string_view& rest) {
  const char* space = " \t\r\v\f";
  const std::size_t b = rest.find_first_not_of(space);
  if (b == std::string_view::npos) {
    rest = {};
    return {};
  }
  const std::size_t e = std::min(rest.find_first_of(space, b), rest.size());
  const std::string_view token = rest.substr(b, e - b);
  rest.remove_prefix(e);
  return token;
}

/// An OBJ file's lines turned into a mesh, with the line of every vertex and triangle.
class ObjParser {
 public:
  ObjParser(const std::string& name, const ObjLimits& limits) : m_name(name), m_limits(limits) {}

  void read(std::string_view text);
  ObjFile finish();

 private:
  [[noreturn]] void fail(int line, const std::string& what) const {
    throw UserError(m_name + ":" + std::to_string(line) + ": " + what);
  }
  void statement(std::string_view keyword, std::string_view rest, int line);
  void vertex(std::string_view rest, int line);
  void face(std::string_view rest, int line);
  int vertex_reference(std::string_view token, int line) const;
  void names(std::string_view rest, bool object);
  int group_id(std::string_view name);
  void check_ranges() const;
  void check_problems(ObjFile& file) const;

  std::string m_name;
  ObjLimits m_limits;
  std::vector<double> m_coords;  // 3 per vertex
  std::vector<int> m_vertex_line;
  std::vector<std::array<int, 3>> m_triangles;
  std::vector<int> m_triangle_line;
  std::vector<std::string> m_group_names;          // in order of first appearance
  std::vector<std::vector<int>> m_group_vertices;  // per group, unsorted
  std::unordered_map<std::string, int> m_group_index;
  int m_object = -1;                                     // the current o's group, or -1
  std::vector<int> m_groups;                             // the current g's groups
  std::map<std::string, std::pair<int, int>> m_ignored;  // keyword -> (first line, count)
};

void ObjParser::read(std::string_view text) {
  int line = 0;
  while (!text.empty()) {
    ++line;
    const std::size_t end = std::min(text.find('\n'), text.size());
    std::string_view rest = text.substr(0, end);
    text.remove_prefix(std::min(end + 1, text.size()));
    // a comment runs from # to the end of the line
    rest = rest.substr(0, std::min(rest.find('#'), rest.size()));
    const std::string_view keyword = next_token(rest);
    if (!keyword.empty()) statement(keyword, rest, line);
  }
}

void ObjParser::statement(std::string_view keyword, std::string_view rest, int line) {
  if (keyword == "v") {
    vertex(rest, line);
  } else if (keyword == "f") {
    face(rest, line);
  } else if (keyword == "g" || keyword == "o") {
    names(rest, keyword == "o");
  } else if (ignored_with_warning(keyword)) {
    auto& seen = m_ignored[std::string(keyword)];
    if (seen.second++ == 0) seen.first = line;
  } else if (!silently_ignored(keyword)) {
    std::string shown(keyword.substr(0, 40));
    fail(line, "unknown statement \"" + shown +
                   "\" (an OBJ mesh has v, f, g and o lines): is this an OBJ file?");
  }
}

void ObjParser::vertex(std::string_view rest, int line) {
  if (static_cast<int>(m_vertex_line.size()) >= m_limits.max_vertices)
    fail(line, "more than " + std::to_string(m_limits.max_vertices) +
                   " vertices, the most a mesh may have");
  // x, y, z (m), then nothing, a weight, or a colour
  double numbers[7];
  int count = 0;
  for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
    if (count == 7) fail(line, "a vertex has 3 coordinates (x y z), got more than 7 numbers");
    std::string_view digits = token;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    double value = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    const std::string shown = "\"" + std::string(token.substr(0, 40)) + "\"";
    if (ec == std::errc::result_out_of_range)
      fail(line, "vertex coordinate " + shown + " is out of the range of a double");
    if (ec != std::errc() || end != digits.data() + digits.size() || digits.empty())
      fail(line, "expected a number as vertex coordinate, got " + shown);
    if (!std::isfinite(value))
      fail(line, "vertex coordinate " + shown + " is not a finite number (NaN or infinite)");
    numbers[count++] = value;
  }
  if (count != 3 && count != 4 && count != 6 && count != 7)
    fail(line, "a vertex has 3 coordinates (x y z), got " + std::to_string(count) + " numbers");
  m_coords.insert(m_coords.end(), numbers, numbers + 3);
  m_vertex_line.push_back(line);
}

int ObjParser::vertex_reference(std::string_view token, int line) const {
  // a, a/b, a/b/c or a//c: only a, the vertex, is used; b and c must be integers or empty
  const std::string shown = "\"" + std::string(token.substr(0, 40)) + "\"";
  std::string_view parts[3];
  int n = 0;
  for (std::string_view rest = token;; ++n) {
    if (n == 3) fail(line, "a face's vertex is a, a/b, a/b/c or a//c, got " + shown);
    const std::size_t slash = std::min(rest.find('/'), rest.size());
    parts[n] = rest.substr(0, slash);
    if (slash == rest.size()) break;
    rest.remove_prefix(slash + 1);
  }
  long long values[3] = {0, 0, 0};
  for (int k = 0; k <= n; ++k) {
    const std::string_view p = parts[k];
    if (p.empty() && k > 0) continue;
    const auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), values[k]);
    if (p.empty() || ec != std::errc() || end != p.data() + p.size())
      fail(line, "a face's vertex is a, a/b, a/b/c or a//c with integers, got " + shown);
  }
  // counted from 1, or from the last vertex so far when negative
  const long long a = values[0];
  const long long so_far = static_cast<long long>(m_vertex_line.size());
  if (a == 0) fail(line, "vertex reference 0 in a face: OBJ counts vertices from 1");
  if (a < 0 && so_far + a < 0)
    fail(line, "vertex reference " + std::to_string(a) + " goes before the first vertex (" +
                   std::to_string(so_far) + " vertices so far)");
  if (a > m_limits.max_vertices)
    fail(line, "vertex reference " + std::to_string(a) + " is beyond the most vertices a mesh " +
                   "may have (" + std::to_string(m_limits.max_vertices) + ")");
  return static_cast<int>(a < 0 ? so_far + a : a - 1);
}

void ObjParser::face(std::string_view rest, int line) {
  std::vector<int> corners;
  for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest))
    corners.push_back(vertex_reference(token, line));
  if (corners.size() < 3)
    fail(line, "a face needs at least 3 vertices, got " + std::to_string(corners.size()));
  if (m_triangles.size() + corners.size() - 2 > static_cast<std::size_t>(m_limits.max_triangles))
    fail(line, "more than " + std::to_string(m_limits.max_triangles) +
                   " triangles, the most a mesh may have");
  // a polygon as a fan around its first vertex
  for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
    m_triangles.push_back({corners[0], corners[k], corners[k + 1]});
    m_triangle_line.push_back(line);
  }
  // its vertices join every group in force
  for (int g : m_groups)
    m_group_vertices[g].insert(m_group_vertices[g].end(), corners.begin(), corners.end());
  if (m_object >= 0 && std::find(m_groups.begin(), m_groups.end(), m_object) == m_groups.end())
    m_group_vertices[m_object].insert(m_group_vertices[m_object].end(), corners.begin(),
                                      corners.end());
}

int ObjParser::group_id(std::string_view name) {
  const auto [it, added] =
      m_group_index.emplace(std::string(name), static_cast<int>(m_group_names.size()));
  if (added) {
    m_group_names.emplace_back(name);
    m_group_vertices.emplace_back();
  }
  return it->second;
}

void ObjParser::names(std::string_view rest, bool object) {
  // o: one name (the rest of the line), and the g names end; g: each word a group
  m_groups.clear();
  if (object) {
    m_object = -1;
    const std::size_t b = rest.find_first_not_of(" \t\r\v\f");
    if (b == std::string_view::npos) return;
    const std::size_t e = rest.find_last_not_of(" \t\r\v\f");
    m_object = group_id(rest.substr(b, e - b + 1));
    return;
  }
  for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest))
    if (std::find(m_groups.begin(), m_groups.end(), group_id(token)) == m_groups.end())
      m_groups.push_back(group_id(token));
}

void ObjParser::check_ranges() const {
  // positive references may point forward: checked once every vertex is known
  const int nv = static_cast<int>(m_vertex_line.size());
  std::vector<std::string> bad;
  for (std::size_t t = 0; t < m_triangles.size(); ++t)
    for (int v : m_triangles[t])
      if (v >= nv) {
        bad.push_back(m_name + ":" + std::to_string(m_triangle_line[t]) +
                      ": face refers to vertex " + std::to_string(v + 1) + ", but the file has " +
                      std::to_string(nv) + " vertices");
        break;
      }
  // one face split into several triangles is named once
  bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
  if (bad.empty()) return;
  std::string message;
  for (std::size_t k = 0; k < bad.size() && k < kProblemsShown; ++k)
    message += (k ? "; " : "") + bad[k];
  if (bad.size() > kProblemsShown)
    message += "; and " + std::to_string(bad.size() - kProblemsShown) + " more";
  throw UserError(message);
}

/// A problem of check_mesh told in the file's terms: its line, and vertices numbered from 1.
std::string describe(const cloth::MeshProblem& p, const std::string& name, const ObjFile& f) {
  using Kind = cloth::MeshProblemKind;
  const auto num = [](int v) { return std::to_string(v + 1); };
  const auto at = [&](int line) { return name + ":" + std::to_string(line) + ": "; };
  const auto edge = [&] {
    return "the edge between vertices " + num(p.vertex) + " and " + num(p.other_vertex);
  };
  const auto tri = [&] {
    const auto& t = f.mesh.triangles[p.triangle];
    return num(t[0]) + ", " + num(t[1]) + ", " + num(t[2]);
  };
  switch (p.kind) {
    case Kind::non_finite_vertex:
      return at(f.vertex_line[p.vertex]) + "vertex " + num(p.vertex) + " is not finite";
    case Kind::index_out_of_range:
      return at(f.triangle_line[p.triangle]) + "face refers to a vertex out of range";
    case Kind::degenerate_triangle:
      return at(f.triangle_line[p.triangle]) + "degenerate triangle (vertices " + tri() +
             "): zero area or a repeated vertex";
    case Kind::oversized_triangle:
      return at(f.triangle_line[p.triangle]) + "triangle (vertices " + tri() +
             ") too large to measure: a side's squared length overflows a double (coordinates "
             "are in metres)";
    case Kind::non_manifold_edge:
      return at(f.triangle_line[p.triangle]) + edge() +
             " is shared by more than two triangles (this face's is the third)";
    case Kind::inconsistent_orientation:
      return at(f.triangle_line[p.triangle]) + "this face runs along " + edge() +
             " the same way as the face on line " +
             std::to_string(f.triangle_line[p.other_triangle]) +
             ": their orientations disagree (list one of them in reverse order)";
    case Kind::bowtie_vertex:
      return at(f.vertex_line[p.vertex]) + "vertex " + num(p.vertex) +
             " is where separate fans of faces meet (a bowtie): give each fan its own vertex";
    case Kind::unused_vertex:
      return at(f.vertex_line[p.vertex]) + "vertex " + num(p.vertex) +
             " is in no face (kept, with no mass)";
  }
  return at(0) + p.message;
}

void ObjParser::check_problems(ObjFile& file) const {
  const std::vector<cloth::MeshProblem> problems = cloth::check_mesh(file.mesh);
  std::string errors;
  int shown = 0, more = 0, unused = 0;
  for (const cloth::MeshProblem& p : problems) {
    if (!p.is_error()) {
      // unused vertices: the first few as warnings, then their number
      if (unused++ < kProblemsShown) file.warnings.push_back(describe(p, m_name, file));
      continue;
    }
    if (shown < kProblemsShown) {
      errors += (shown++ ? "; " : "") + describe(p, m_name, file);
    } else {
      ++more;
    }
  }
  if (unused > kProblemsShown)
    file.warnings.push_back(m_name + ": and " + std::to_string(unused - kProblemsShown) +
                            " more vertices in no face");
  if (more > 0) errors += "; and " + std::to_string(more) + " more";
  if (!errors.empty()) throw UserError(errors);
}

ObjFile ObjParser::finish() {
  if (m_triangles.empty()) throw UserError(m_name + ": no faces (f lines): not a triangle mesh");
  check_ranges();
  ObjFile file;
  const int nv = static_cast<int>(m_vertex_line.size());
  file.mesh.x.resize(3, nv);
  for (int v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) file.mesh.x(k, v) = m_coords[3 * v + k];
  file.mesh.triangles = m_triangles;
  for (std::size_t g = 0; g < m_group_names.size(); ++g) {
    std::vector<int> vs = m_group_vertices[g];
    std::sort(vs.begin(), vs.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
    file.mesh.groups.emplace_back(m_group_names[g], std::move(vs));
  }
  file.vertex_line = m_vertex_line;
  file.triangle_line = m_triangle_line;
  // the statements skipped, one warning per keyword
  for (const auto& [keyword, seen] : m_ignored)
    file.warnings.push_back(m_name + ":" + std::to_string(seen.first) + ": \"" + keyword +
                            "\" ignored (" + std::to_string(seen.second) +
                            " lines): clothbench reads only v, f, g and o");
  check_problems(file);
  return file;
}

}  // namespace

ObjFile read_obj_text(const std::string& text, const std::string& name, ObjLimits limits) {
  if (text.size() > limits.max_bytes)
    throw UserError(name + ": " + std::to_string(text.size()) + " bytes, more than the " +
                    std::to_string(limits.max_bytes) + " a mesh file may have");
  ObjParser parser(name, limits);
  parser.read(text);
  return parser.finish();
}

ObjFile read_obj_file(const std::string& path, ObjLimits limits) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw UserError(path + ": cannot open (a folder, not a file)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UserError(path + ": cannot open (" + std::strerror(errno) + ")");
  // the size first, so that an enormous file is refused before it is read
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > limits.max_bytes)
    throw UserError(path + ": " + std::to_string(size) + " bytes, more than the " +
                    std::to_string(limits.max_bytes) + " a mesh file may have");
  // read in chunks, never past the limit: a device or a pipe (/dev/zero) has no size to check
  std::string text;
  if (!ec) text.reserve(static_cast<std::size_t>(size));
  std::vector<char> chunk(1 << 16);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > limits.max_bytes)
      throw UserError(path + ": more than the " + std::to_string(limits.max_bytes) +
                      " bytes a mesh file may have");
  }
  if (in.bad()) throw UserError(path + ": cannot read (" + std::strerror(errno) + ")");
  return read_obj_text(text, path, limits);
}

cloth::TriangleMesh read_obj(const std::string& path, ObjLimits limits) {
  return read_obj_file(path, limits).mesh;
}

}  // namespace clothbench
