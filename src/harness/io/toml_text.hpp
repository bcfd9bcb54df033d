#pragma once
/// @file toml_text.hpp
/// Values as TOML text, for the scenario writer and for "got ..." in messages.

#include <toml++/toml.h>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace clothbench {

/// s as a TOML basic string, quoted and escaped.
std::string toml_string(std::string_view s);

/// A value as the user wrote it, for "got ..." in messages (arrays past 6 entries elided).
std::string describe(const toml::node& n);

/// Deepest nesting of arrays and inline tables, and most parts of one dotted key, that a
/// scenario or tolerance file may have: far above what the formats use (3), far below what
/// would exhaust the TOML parser's stack.
inline constexpr int kMaxTomlDepth = 64;

/// What makes text structurally extreme for the TOML parser ("a dotted key of more than 64
/// parts"), and on which line (from 1), or nullopt when nothing does. Strings and comments are
/// skipped; the text is not otherwise checked (the parser does that).
std::optional<std::pair<int, std::string>> toml_structure_problem(std::string_view text);

}  // namespace clothbench
