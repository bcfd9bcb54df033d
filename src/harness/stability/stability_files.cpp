#include "harness/stability/stability_files.hpp"

#include <cmath>
#include <limits>
#include <utility>

#include "cloth/model/constants.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/io/text_file.hpp"
#include "harness/io/user_error.hpp"
#include "harness/run/trajectory_files.hpp"
#include "harness/scenario/scenario_loader.hpp"
#include "harness/scenario/scenario_writer.hpp"

namespace clothbench {

namespace {

using cloth::kInf;
using cloth::kNaN;

std::string field(double v) {
  return std::isfinite(v) ? format_double(v) : std::string();
}

/// The options line and the scenario of a sidecar text: the comment lines hold the options.
std::pair<std::string, std::string> options_and_scenario(const std::string& text) {
  size_t at = 0;
  while (at < text.size() && text[at] == '#') {
    const size_t end = text.find('\n', at);
    at = end == std::string::npos ? text.size() : end + 1;
  }
  const size_t from = text.find("--dt-max");
  const std::string options =
      from < at ? text.substr(from, text.find('\n', from) - from) : std::string("(none recorded)");
  return std::make_pair(options, text.substr(at));
}

}  // namespace

const char* const kStabilitySidecar = "stability_scenario.toml";
const char* const kStabilityModes = "stability_modes";

void write_mode(const std::string& path, const cloth::Matrix3X& mode) {
  const std::vector<float> values(mode.data(), mode.data() + mode.size());  // row-major
  AtomicFile f(path);
  f.write(npy_float32({3, static_cast<size_t>(mode.cols())}, values));
  f.commit();
}

const std::vector<std::string>& stability_header() {
  static const std::vector<std::string> header = output_header("stability.csv");
  return header;
}

std::vector<std::string> stability_fields(const StabilityRow& row) {
  return {row.engine,
          row.integrator,
          field(row.stable_dt),
          field(row.first_unstable_dt),
          field(row.predicted_dt),
          field(row.ratio),
          row.cause,
          std::to_string(row.runs),
          row.rerun,
          row.rerun_unstable,
          row.method,
          field(row.growth.stable_dt),
          field(row.growth.first_unstable_dt),
          field(row.growth.growth_rate),
          field(row.growth.physical_rate),
          field(row.growth_ratio),
          row.growth.cause,
          field(row.growth.mode_energy[0]),
          field(row.growth.mode_energy[1]),
          field(row.growth.mode_energy[2]),
          std::to_string(row.growth.steps),
          std::to_string(row.blowup_steps)};
}

StabilityRow stability_row(const CsvRecord& record) {
  StabilityRow row;
  row.engine = record.text(0);
  row.integrator = record.text(1);
  row.stable_dt = record.number(2, kNaN);
  row.first_unstable_dt = record.number(3, kInf);
  row.predicted_dt = record.number(4, kNaN);
  row.ratio = record.number(5, kNaN);
  row.cause = record.text(6);
  row.runs = static_cast<int>(record.integer(7));
  row.rerun = record.text(8);
  row.rerun_unstable = record.text(9);
  row.method = record.text(10);
  row.growth.stable_dt = record.number(11, kNaN);
  row.growth.first_unstable_dt = record.number(12, kInf);
  row.growth.growth_rate = record.number(13, kNaN);
  row.growth.physical_rate = record.number(14, kNaN);
  row.growth_ratio = record.number(15, kNaN);
  row.growth.cause = record.text(16);
  for (int k = 0; k < 3; ++k) row.growth.mode_energy[size_t(k)] = record.number(17 + k, kNaN);
  row.growth.steps = record.integer(20);
  row.blowup_steps = record.integer(21);
  row.resumed = true;
  return row;
}

std::string stability_sidecar_text(const Scenario& sc, const StabilityOptions& o) {
  return "# the stability sweep whose rows stability.csv holds; --resume continues it only\n"
         "# with this scenario and these options:\n"
         "#   --dt-max " +
         format_double(o.dt_max) + " --rel-tol " + format_double(o.rel_tol) + " --method " +
         stability_method_name(o.method) + " --perturbation " + format_double(o.perturbation) +
         " --growth-tol " + format_double(o.growth_tol) +
         (sc.max_run_seconds > 0 ? " --max-run-seconds " + format_double(sc.max_run_seconds)
                                 : std::string()) +
         "\n" + scenario_to_toml(sc);
}

void check_stability_resumable(const std::string& dir, const Scenario& sc,
                               const StabilityOptions& o) {
  const std::string csv = dir + "stability.csv", sidecar = dir + kStabilitySidecar;
  const std::string earlier = read_text(sidecar);
  const std::string now = stability_sidecar_text(sc, o);
  if (earlier.empty()) {
    if (!read_text(csv).empty())
      throw UserError(csv + ": cannot resume: there is no " + kStabilitySidecar +
                      " beside it to say which scenario and options its rows come "
                      "from; run without --resume or choose another output folder");
    return;
  }
  if (earlier == now) return;
  // say which part differs
  const auto [earlier_options, earlier_scenario] = options_and_scenario(earlier);
  const auto [options, scenario] = options_and_scenario(now);
  const std::string what =
      earlier_scenario != scenario
          ? "another scenario (or other --set overrides or --engine choices)"
          : "other options (" + earlier_options + " then, " + options + " now)";
  throw UserError(sidecar + ": cannot resume: the folder holds a stability sweep of " + what +
                  "; run without --resume or choose another output folder");
}

}  // namespace clothbench
