#pragma once
/// @file number_format.hpp
/// Doubles as the shortest text that reads back as exactly the same value, for scenario files
/// and messages alike (the loader, the Bullet adapters' refusals, the CSV writer).

#include <string>

namespace cloth {

/// Shortest decimal that reads back as exactly x: plain for everyday magnitudes ("0.0003",
/// "20000", "-3"), scientific for the very small and very large ("1e-08").
std::string shortest_decimal(double x);

/// x as a TOML float: shortest_decimal with ".0" where it would otherwise read as an integer
/// ("20000.0"), and "nan", "inf", "-inf".
std::string toml_double(double x);

/// x to `digits` significant digits (printf's %g: "0.0123", "1.235e+04", "nan", "inf"), for
/// what a person reads on the terminal or in a note; the files keep every digit.
std::string significant(double x, int digits);

}  // namespace cloth
