#pragma once
/// @file map_grid.hpp
/// The grid of a stability map: the scenario keys `clothbench map --vary` varies and their
/// values, and the points of their product.

#include <string>
#include <vector>

namespace clothbench {

/// One varied key: a scenario key (as --set names it) and its values in the order swept.
struct VariedKey {
  std::string key;                  // e.g. cloth.stiffness.structural, cloth.particles
  std::vector<std::string> values;  // each as written in map.csv (a TOML value)
  /// The --set override of value i ("cloth.particles=33" sets a square 33 x 33 grid).
  std::string override_text(size_t i) const;
};

/// Parses "KEY=LIST_OR_RANGE": a list "v1,v2,..." of TOML values, or a range "A:B:log:N" /
/// "A:B:lin:N" of N >= 2 numbers from A to B (log: evenly spaced in log10, A and B > 0).
/// cloth.particles takes whole numbers >= 2, each the edge of a square grid (a range is rounded
/// to whole numbers). Throws UserError naming the option for anything else, for a key given
/// twice, or a value given twice.
VariedKey parse_varied_key(const std::string& text);

/// One point of the grid: the index of each varied key's value.
using GridPoint = std::vector<size_t>;

/// Every point of the product of the keys' values, the first key varying slowest.
std::vector<GridPoint> grid_points(const std::vector<VariedKey>& keys);

}  // namespace clothbench
