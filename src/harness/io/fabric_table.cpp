#include "harness/io/fabric_table.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "format/number_format.hpp"
#include "harness/io/embedded_fabrics.hpp"
#include "harness/io/toml_text.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench {

namespace {

// the keys a row may have
const std::vector<std::string_view> kFabricKeys = {"name",
                                                   "source",
                                                   "checked",
                                                   "areal_density",
                                                   "tensile_stiffness_warp",
                                                   "tensile_stiffness_weft",
                                                   "shear_stiffness",
                                                   "bending_rigidity_warp",
                                                   "bending_rigidity_weft",
                                                   "bending_rigidity",
                                                   "thickness",
                                                   "drape_coefficient",
                                                   "arcsim_stretching_row0",
                                                   "arcsim_bending_first",
                                                   "notes"};

/// A plausible range in a unit, and the unit a value outside it was probably written in.
struct Range {
  double lo;
  double hi;
  const char* unit;
  const char* hint;  // "" or "; 324 looks like g/m^2"-style advice
};
// bounds wide enough for any fabric, narrow enough to catch a value in the wrong unit
const Range kDensity{0.005, 5.0, "kg/m^2",
                     "; a value over 5 is probably in g/m^2 (divide by 1000)"};
const Range kTensile{0.1, 1e6, "N/m", ""};
const Range kShear{0.01, 1e5, "N/m per radian", ""};
const Range kBending{1e-9, 1e-2, "N m", "; a value over 0.01 is probably in uN m (times 1e-6)"};
const Range kThickness{1e-5, 0.05, "m", "; a value over 0.05 is probably in mm (times 1e-3)"};
const Range kFraction{0.0, 1.0, "(a fraction, 0 to 1)", "; a value over 1 is probably in %"};

/// Reads one row, each value checked where it is read.
class RowReader {
 public:
  RowReader(const toml::table& row, const std::string& file) : m_row(row), m_file(file) {}

  [[noreturn]] void fail(const toml::node* n, std::string_view key,
                         const std::string& problem) const {
    const auto line = n ? std::max<toml::source_index>(n->source().begin.line, 1) : 1;
    throw UserError(m_file + ":" + std::to_string(line) + ": fabric." + std::string(key) + ": " +
                    problem);
  }

  std::string text(std::string_view key, bool required) const {
    const toml::node* n = m_row.get(key);
    if (!n && required) fail(&m_row, key, "missing: every fabric needs " + std::string(key));
    if (!n) return "";
    if (!n->is_string() || n->as_string()->get().empty())
      fail(n, key, "expected a non-empty string, got " + describe(*n));
    return n->as_string()->get();
  }

  std::optional<double> number(std::string_view key, const Range& range) const {
    const toml::node* n = m_row.get(key);
    if (!n) return std::nullopt;
    const auto x = n->value<double>();
    if (!x || !std::isfinite(*x)) fail(n, key, "expected a number, got " + describe(*n));
    if (*x < range.lo || *x > range.hi || (range.lo == 0.0 && *x < 0))
      fail(n, key,
           "expected " + std::string(range.unit) + " from " + cloth::toml_double(range.lo) +
               " to " + cloth::toml_double(range.hi) + ", got " + describe(*n) + range.hint);
    return *x;
  }

  double required(std::string_view key, const Range& range) const {
    if (!m_row.get(key)) fail(&m_row, key, "missing: every fabric needs " + std::string(key));
    return *number(key, range);
  }

  void numbers(std::string_view key, size_t count) const {
    const toml::node* n = m_row.get(key);
    if (!n) return;
    const toml::array* a = n->as_array();
    bool ok = a && a->size() == count;
    for (size_t k = 0; ok && k < count; ++k) ok = a->get(k)->value<double>().has_value();
    if (!ok)
      fail(n, key,
           "expected an array of " + std::to_string(count) + " numbers, got " + describe(*n));
  }

  const toml::table& row() const { return m_row; }

 private:
  const toml::table& m_row;
  const std::string& m_file;
};

/// Bending: the warp/weft pair, or one rigidity when the source gives no direction.
void read_bending(const RowReader& r, Fabric& f) {
  const toml::node* one = r.row().get("bending_rigidity");
  const toml::node* warp = r.row().get("bending_rigidity_warp");
  const toml::node* weft = r.row().get("bending_rigidity_weft");
  if (one && (warp || weft))
    r.fail(one, "bending_rigidity",
           "give bending_rigidity (no direction) or bending_rigidity_warp and _weft, not both");
  if (one) {
    f.bending_warp = f.bending_weft = r.required("bending_rigidity", kBending);
    f.bending_directional = false;
    return;
  }
  if (!warp && !weft)
    r.fail(&r.row(), "bending_rigidity",
           "missing: give bending_rigidity_warp and bending_rigidity_weft (N m), or "
           "bending_rigidity");
  f.bending_warp = r.required("bending_rigidity_warp", kBending);
  f.bending_weft = r.required("bending_rigidity_weft", kBending);
}

/// Tensile stiffness: both directions or neither.
void read_tensile(const RowReader& r, Fabric& f) {
  f.tensile_warp = r.number("tensile_stiffness_warp", kTensile);
  f.tensile_weft = r.number("tensile_stiffness_weft", kTensile);
  if (f.tensile_warp.has_value() != f.tensile_weft.has_value()) {
    const char* missing = f.tensile_warp ? "tensile_stiffness_weft" : "tensile_stiffness_warp";
    r.fail(&r.row(), missing,
           "missing: tensile stiffness is given for both warp and weft or neither");
  }
}

/// Name: lowercase letters, digits and hyphens, as a scenario writes it.
void check_name(const RowReader& r, const std::string& name) {
  const bool ok = std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return std::islower(c) || std::isdigit(c) || c == '-';
  });
  if (!ok)
    r.fail(r.row().get("name"), "name",
           "expected lowercase letters, digits and hyphens, got " + toml_string(name));
}

/// One [[fabric]] table.
Fabric read_row(const toml::table& row, const std::string& file) {
  const RowReader r(row, file);
  for (const auto& [k, v] : row)
    if (std::find(kFabricKeys.begin(), kFabricKeys.end(), k.str()) == kFabricKeys.end())
      r.fail(&v, k.str(), "unknown key");
  Fabric f;
  f.line = static_cast<int>(std::max<toml::source_index>(row.source().begin.line, 1));
  f.name = r.text("name", true);
  check_name(r, f.name);
  f.source = r.text("source", true);
  const toml::node* checked = row.get("checked");
  if (!checked) r.fail(&row, "checked", "missing: say whether the row was checked at its source");
  if (!checked->is_boolean())
    r.fail(checked, "checked", "expected true or false, got " + describe(*checked));
  f.checked = checked->as_boolean()->get();
  f.areal_density = r.required("areal_density", kDensity);
  read_tensile(r, f);
  f.shear_stiffness = r.number("shear_stiffness", kShear);
  read_bending(r, f);
  f.thickness = r.number("thickness", kThickness);
  f.drape_coefficient = r.number("drape_coefficient", kFraction);
  r.numbers("arcsim_stretching_row0", 4);
  r.numbers("arcsim_bending_first", 3);
  f.notes = r.text("notes", false);
  return f;
}

/// The parsed document, or a UserError at the parser's line.
toml::table parse_document(std::string_view text, const std::string& file) {
  if (const auto problem = toml_structure_problem(text))
    throw UserError(file + ":" + std::to_string(problem->first) + ": " + problem->second);
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw UserError(file + ":" + std::to_string(e.source().begin.line) + ": " +
                    std::string(e.description()));
  }
}

}  // namespace

std::optional<double> Fabric::tensile_mean() const {
  if (!tensile_warp || !tensile_weft) return std::nullopt;
  return 0.5 * (*tensile_warp + *tensile_weft);
}

const Fabric* FabricTable::find(std::string_view name) const {
  for (const Fabric& f : fabrics)
    if (f.name == name) return &f;
  return nullptr;
}

std::vector<std::string_view> FabricTable::names() const {
  std::vector<std::string_view> out;
  for (const Fabric& f : fabrics) out.push_back(f.name);
  return out;
}

FabricTable parse_fabric_table(std::string_view text, const std::string& source_name) {
  const toml::table doc = parse_document(text, source_name);
  FabricTable table{source_name, {}};
  for (const auto& [k, v] : doc)
    if (k.str() != "fabric")
      throw UserError(source_name + ":" + std::to_string(v.source().begin.line) + ": " +
                      std::string(k.str()) + ": unknown key (expected [[fabric]] tables)");
  const toml::array* rows = doc["fabric"].as_array();
  if (!rows || rows->empty() || !rows->is_array_of_tables())
    throw UserError(source_name + ":1: expected [[fabric]] tables, found none");
  for (const toml::node& row : *rows) {
    Fabric f = read_row(*row.as_table(), source_name);
    if (table.find(f.name))
      throw UserError(source_name + ":" + std::to_string(f.line) +
                      ": fabric.name: " + toml_string(f.name) + " is given twice");
    table.fabrics.push_back(std::move(f));
  }
  return table;
}

FabricTable read_fabric_table(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UserError(path + ": cannot read the fabric file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_fabric_table(text.str(), path);
}

const FabricTable& shipped_fabrics() {
  // parsed once; the compiled-in file is checked by the tests, so it parses
  static const FabricTable table =
      parse_fabric_table(std::string_view(reinterpret_cast<const char*>(generated::kFabrics),
                                          sizeof generated::kFabrics),
                         "reference/fabrics/fabrics.toml");
  return table;
}

}  // namespace clothbench
