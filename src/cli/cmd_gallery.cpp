/// @file cmd_gallery.cpp
/// `clothbench gallery`: analysis/gallery.py on several run folders (one page of every run's
/// final shape in every engine, with its summary and test metrics); everything after `gallery`
/// goes to the script.

#include "commands.hpp"

namespace clothbench::cli {

Command add_gallery_command(CLI::App& app) {
  CLI::App* gallery = app.add_subcommand(
      "gallery",
      "One page of several runs (runs analysis/gallery.py with /usr/bin/python3): DIR...\n"
      "--out OUTDIR [--title TEXT] [--svg]; each run's final shape in every engine, its\n"
      "summary and its [test] metrics; `clothbench gallery --help` shows the script's help.");
  gallery->set_help_flag();  // --help goes to the script
  gallery->allow_extras();
  gallery->prefix_command();
  return {gallery, [gallery] { return run_analysis_script("gallery.py", gallery->remaining()); }};
}

}  // namespace clothbench::cli
