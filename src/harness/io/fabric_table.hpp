#pragma once
/// @file fabric_table.hpp
/// The fabric presets: reference/fabrics/fabrics.toml, published measurements of real fabrics
/// (areal density, tensile, shear and bending stiffness, thickness, drape coefficient), each
/// row with its source. Read strictly: an unknown key, a missing field, a value outside its
/// unit's plausible range is a UserError naming the file and line.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace clothbench {

/// One fabric of the table, in SI units.
struct Fabric {
  std::string name;                         // the preset's name ([cloth] fabric = name)
  std::string source;                       // citation
  bool checked = false;                     // the numbers were read at the source
  double areal_density = 0.0;               // kg/m^2
  std::optional<double> tensile_warp;       // N/m, tensile stiffness per width along the warp
  std::optional<double> tensile_weft;       // N/m, along the weft (set with tensile_warp)
  std::optional<double> shear_stiffness;    // N/m per radian of in-plane shear
  double bending_warp = 0.0;                // N m, flexural rigidity per width, warp strip
  double bending_weft = 0.0;                // N m, weft strip (= bending_warp without a direction)
  bool bending_directional = true;          // false: the source gives one rigidity
  std::optional<double> thickness;          // m
  std::optional<double> drape_coefficient;  // Cusick drape coefficient, 0 to 1
  std::string notes;
  int line = 0;  // line of the row's [[fabric]] header in its file

  /// Mean of the warp and weft tensile stiffness (N/m); nullopt without tensile data.
  std::optional<double> tensile_mean() const;
  /// Mean of the warp and weft bending rigidity (N m).
  double bending_mean() const { return 0.5 * (bending_warp + bending_weft); }
};

/// The rows of a fabric file and the file's name for messages.
struct FabricTable {
  std::string source;  // file name as errors give it
  std::vector<Fabric> fabrics;

  /// The fabric named name, or null.
  const Fabric* find(std::string_view name) const;
  /// The fabrics' names in file order.
  std::vector<std::string_view> names() const;
};

/// Parses the text of a fabric file; errors name source_name and the line. Throws UserError.
FabricTable parse_fabric_table(std::string_view text, const std::string& source_name);

/// Reads a fabric file from disk. Throws UserError when it cannot be read or is malformed.
FabricTable read_fabric_table(const std::string& path);

/// The table shipped with clothbench: reference/fabrics/fabrics.toml, compiled in.
const FabricTable& shipped_fabrics();

}  // namespace clothbench
