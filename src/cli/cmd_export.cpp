/// @file cmd_export.cpp
/// `clothbench export`: analysis/export.py on a run folder's trajectories (OBJ sequences for
/// Blender, VTK polydata with a .pvd time series for ParaView); everything after `export` goes
/// to the script.

#include "commands.hpp"

namespace clothbench::cli {

Command add_export_command(CLI::App& app) {
  CLI::App* exp = app.add_subcommand(
      "export",
      "A run's trajectories as files other tools open (runs analysis/export.py with\n"
      "/usr/bin/python3): DIR --format obj|vtk [--engine NAME]... [--out OUTDIR];\n"
      "`clothbench export --help` shows the script's own help.");
  exp->set_help_flag();  // --help goes to the script
  exp->allow_extras();
  exp->prefix_command();
  return {exp, [exp] { return run_analysis_script("export.py", exp->remaining()); }};
}

}  // namespace clothbench::cli
