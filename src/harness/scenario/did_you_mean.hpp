#pragma once
/// @file did_you_mean.hpp
/// Suggestions for a misspelt key, value or name: the nearest known word by edit distance.

#include <cstddef>
#include <string>
#include <string_view>

#include "harness/scenario/scenario_format.hpp"

namespace clothbench {

/// Levenshtein distance of a and b, letters compared case-insensitively.
size_t edit_distance(std::string_view a, std::string_view b);

/// "; did you mean "x"?" when word is a near miss of one of known, else "".
std::string near_miss(std::string_view word, const Keys& known);

/// "; did you mean "x"?" for a near miss, else " (expected one of: ...)".
std::string suggest(std::string_view word, const Keys& known);

}  // namespace clothbench
