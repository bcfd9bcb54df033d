#pragma once
/// @file text_file.hpp
/// Whole files as text, for the readers of what clothbench wrote earlier.

#include <string>

namespace clothbench {

/// The whole text of the file at path ("" when it cannot be read).
std::string read_text(const std::string& path);

/// The whole text of the file at path; throws UserError "cannot read PATH" when it cannot be
/// read.
std::string read_existing_text(const std::string& path);

}  // namespace clothbench
