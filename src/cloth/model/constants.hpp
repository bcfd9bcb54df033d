#pragma once
/// @file constants.hpp
/// Pi, and the NaN and infinity that stand for "not measured" and "no limit", for the files that
/// name them as constants (one definition, not one per file).

#include <limits>

namespace cloth {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace cloth
