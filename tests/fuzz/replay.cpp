/// @file replay.cpp
/// Replays every saved fuzz input (tests/data/fuzz/<target>/*: crashes the fuzzers found,
/// fixed since) and the fuzzers' seed corpus through the same entries in the normal build, so
/// that a bug found once stays found. An input that makes an entry throw anything but a
/// UserError fails here; a crash fails the whole test program (and the asan build reports it).

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_entries.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kSource = CLOTHBENCH_SOURCE_DIR;

std::vector<fs::path> files_under(const fs::path& dir) {
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("every saved fuzz input and seed is refused or accepted, never a bug", "[fuzz]") {
  for (const auto& [name, entry] : clothbench::fuzz::entries()) {
    // the target's saved inputs, and the seeds every target starts from
    std::vector<fs::path> inputs = files_under(kSource / "tests" / "data" / "fuzz" / name);
    for (const char* seeds : {"scenarios", "tests/data/good", "tests/data/bad"})
      for (const fs::path& p : files_under(kSource / seeds)) inputs.push_back(p);
    for (const fs::path& p : files_under(kSource / "reference" / "baselines")) inputs.push_back(p);
    for (const fs::path& p : inputs) {
      INFO(name << " <- " << p.string());
      const std::string data = bytes_of(p);
      CHECK_NOTHROW(entry(reinterpret_cast<const std::uint8_t*>(data.data()), data.size()));
    }
  }
}
