#pragma once
/// @file temp_dir.hpp
/// A scratch folder for one test: fresh when made, removed when the test ends.

#include <unistd.h>

#include <filesystem>
#include <string>

namespace clothbench::test {

/// A folder under the system's temporary folder, named after the test and this process (so
/// tests running at once under ctest -j never share one), removed at the end of its scope.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() /
             ("clothbench-" + name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string str() const { return path.string(); }
};

}  // namespace clothbench::test
