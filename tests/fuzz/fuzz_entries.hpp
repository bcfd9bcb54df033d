#pragma once
/// @file fuzz_entries.hpp
/// What the fuzz targets feed their input to, shared with the replay test that runs every
/// saved input through the same code in the normal build. Each entry returns normally for
/// input clothbench accepts or refuses as a user error (UserError); anything else it lets
/// escape (an internal error, a bug), and a crash or undefined behaviour is a bug too.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace clothbench::fuzz {

/// The input as a scenario file's text.
void scenario_text(const std::uint8_t* data, std::size_t size);

/// Each line of the input as a --set override of the seed scene.
void overrides(const std::uint8_t* data, std::size_t size);

/// The input as a CSV file read back (a sweep to resume, a baseline): every field read as a
/// number and as an integer.
void csv_file(const std::uint8_t* data, std::size_t size);

/// The input as a baseline's tolerances.toml.
void tolerances_file(const std::uint8_t* data, std::size_t size);

/// The input as an OBJ mesh file's text; what the reader accepts must be a usable mesh (every
/// index in range, a line per vertex and per triangle).
void obj_text(const std::uint8_t* data, std::size_t size);

/// The entries by name, for scripts/fuzz and the replay test: "scenario", "overrides", "csv",
/// "tolerances", "obj".
using Entry = void (*)(const std::uint8_t*, std::size_t);
const std::vector<std::pair<std::string, Entry>>& entries();

}  // namespace clothbench::fuzz
