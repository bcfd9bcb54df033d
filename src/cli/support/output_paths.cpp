#include "output_paths.hpp"

#include <filesystem>
#include <system_error>

#include "harness/io/output_lock.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench::cli {

namespace fs = std::filesystem;

namespace {

/// The path with every symlink resolved as far as it exists (where a write would land).
fs::path resolved(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
  return ec ? fs::absolute(path).lexically_normal() : p;
}

/// True when inner is folder or lies below it.
bool inside(const fs::path& inner, const fs::path& folder) {
  auto f = folder.begin(), i = inner.begin();
  for (; f != folder.end(); ++f, ++i)
    if (i == inner.end() || *i != *f) return false;
  return true;
}

/// Throws when the file at p (given as arg) lies in a folder another command has locked.
void refuse_locked_folder(const OutputFileArg& arg, const fs::path& p) {
  for (fs::path dir = p.parent_path(); !dir.empty(); dir = dir.parent_path()) {
    const std::string holder = lock_holder(dir.string());
    if (!holder.empty())
      throw UserError(arg.option + " " + arg.path + ": the folder " + dir.string() +
                      " is in use by another clothbench command (" + holder +
                      "); write the report elsewhere");
    if (dir == dir.root_path()) break;
  }
}

/// Throws when p (given as arg) is one of the inputs or lies in an input folder.
void refuse_input(const OutputFileArg& arg, const fs::path& p, const CommandInputs& inputs) {
  for (const std::string& f : inputs.files)
    if (resolved(f) == p)
      throw UserError(arg.option + " " + arg.path + " is the scenario file " + f +
                      " this command reads; write the report elsewhere");
  for (const std::string& d : inputs.folders)
    if (inside(p, resolved(d)))
      throw UserError(arg.option + " " + arg.path + " lies in the folder " + d +
                      " this command reads (the baselines); write the report elsewhere");
}

}  // namespace

void check_output_files(const std::vector<OutputFileArg>& outputs, const CommandInputs& inputs) {
  std::vector<std::pair<fs::path, const OutputFileArg*>> seen;
  for (const OutputFileArg& arg : outputs) {
    if (arg.path.empty()) continue;
    const fs::path p = arg.path == "-" ? fs::path("-") : resolved(arg.path);
    for (const auto& [q, other] : seen)
      if (q == p)
        throw UserError(arg.option + " and " + other->option + " both name " +
                        (arg.path == "-" ? std::string("standard output (-)") : arg.path) +
                        "; give each report its own file");
    seen.emplace_back(p, &arg);
    if (arg.path == "-") continue;
    std::error_code ec;
    if (fs::is_directory(p, ec))
      throw UserError(arg.option + " " + arg.path + " is a folder; give a file name");
    refuse_input(arg, p, inputs);
    refuse_locked_folder(arg, p);
  }
}

}  // namespace clothbench::cli
