#pragma once
/// @file commands.hpp
/// The subcommands of clothbench: each add_*_command adds one to the app with its options and
/// returns how to execute it once the command line is parsed (cmd_<name>.cpp holds both).

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace clothbench::cli {

/// One subcommand added to the app; its parsed options live in the closure of execute.
struct Command {
  CLI::App* app = nullptr;           // the subcommand; *app is true when the user chose it
  std::function<int()> execute;      // runs it with the parsed options; returns the exit status
  bool keeps_finished_rows = false;  // a sweep: Ctrl-C keeps its finished rows (--resume)
};

/// `clothbench run`: every engine of a scenario, frames and summary CSVs.
Command add_run_command(CLI::App& app);
/// `clothbench stability`: the largest stable time step, searched and predicted.
Command add_stability_command(CLI::App& app);
/// `clothbench map`: the stability search over a grid of one or two varied scenario keys.
Command add_map_command(CLI::App& app);
/// `clothbench merge`: the shards of a sweep joined into the unsharded sweep's files.
Command add_merge_command(CLI::App& app);
/// `clothbench accuracy`: error against a fine reference and cost over a time-step sweep.
Command add_accuracy_command(CLI::App& app);
/// `clothbench fit`: each engine's parameters fitted so that its metrics hit their targets.
Command add_fit_command(CLI::App& app);
/// `clothbench check`: the regression gates against the recorded baselines.
Command add_check_command(CLI::App& app);
/// `clothbench report`: analysis/report.py on an output folder.
Command add_report_command(CLI::App& app);
/// `clothbench export`: analysis/export.py (OBJ and VTK sequences of a run's trajectories).
Command add_export_command(CLI::App& app);
/// `clothbench gallery`: analysis/gallery.py (one page of several runs' final shapes).
Command add_gallery_command(CLI::App& app);
/// Runs analysis/<name> with Debian's python3 (CLOTHBENCH_PYTHON overrides) and args; returns
/// its exit status (128 + the signal that ended it); a python that cannot start is exit 2.
int run_analysis_script(const std::string& name, const std::vector<std::string>& args);
/// `clothbench list`: the shipped scenarios, engine kinds and integrators.
Command add_list_command(CLI::App& app);
/// `clothbench schema`: the scenario keys and the output files' columns as Markdown tables.
Command add_schema_command(CLI::App& app);

}  // namespace clothbench::cli
