#pragma once
/// @file output_paths.hpp
/// Output files named on the command line (check's --junit and --json), checked before any
/// work starts, so that a report never replaces an input or another command's file.

#include <string>
#include <vector>

namespace clothbench::cli {

/// One output file: the option that names it and the path given ("-" is standard output).
struct OutputFileArg {
  std::string option;  // "--junit"
  std::string path;
};

/// What a command reads: files it must never write over and folders it must never write in.
struct CommandInputs {
  std::vector<std::string> files;    // scenario files
  std::vector<std::string> folders;  // the baseline folder
};

/// Throws UserError, naming the option and the path, when an output file is a folder, is one
/// of the inputs or lies in an input folder (symlinks followed), lies in a folder another
/// clothbench command holds (its lock), or is the same file as another output; "-" (standard
/// output) may be given once.
void check_output_files(const std::vector<OutputFileArg>& outputs, const CommandInputs& inputs);

}  // namespace clothbench::cli
