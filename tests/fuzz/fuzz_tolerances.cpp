/// @file fuzz_tolerances.cpp
/// libFuzzer target: clothbench::fuzz::tolerances_file (see fuzz_entries.hpp). Built by the
/// fuzz preset.

#include <cstddef>
#include <cstdint>

#include "fuzz_entries.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  clothbench::fuzz::tolerances_file(data, size);
  return 0;
}
