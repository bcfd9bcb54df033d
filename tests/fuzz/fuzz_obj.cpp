/// @file fuzz_obj.cpp
/// libFuzzer target: clothbench::fuzz::obj_text (see fuzz_entries.hpp). Built by the fuzz preset.

#include <cstddef>
#include <cstdint>

#include "fuzz_entries.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  clothbench::fuzz::obj_text(data, size);
  return 0;
}
