#pragma once
/// @file toml_text.hpp
/// Values as TOML text, for the scenario writer and for "got ..." in messages.

#include <toml++/toml.h>
#include <string>
#include <string_view>

namespace clothbench {

/// s as a TOML basic string, quoted and escaped.
std::string toml_string(std::string_view s);

/// A value as the user wrote it, for "got ..." in messages (arrays past 6 entries elided).
std::string describe(const toml::node& n);

}  // namespace clothbench
