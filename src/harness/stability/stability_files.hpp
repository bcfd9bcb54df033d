#pragma once
/// @file stability_files.hpp
/// The files of a stability sweep: stability.csv rows to and from StabilityRow, and the
/// stability_scenario.toml beside them that says which sweep they belong to (for --resume).

#include <string>
#include <vector>

#include "cloth/model/types.hpp"
#include "harness/io/csv_reader.hpp"
#include "harness/scenario/scenario.hpp"
#include "harness/stability/stability_sweep.hpp"

namespace clothbench {

/// The columns of stability.csv.
const std::vector<std::string>& stability_header();

/// Name of the file beside stability.csv that records the scenario and options.
extern const char* const kStabilitySidecar;

/// Name of the folder beside stability.csv that holds the growing modes, ROW.npy each.
extern const char* const kStabilityModes;

/// Writes mode (3 by #P) to path as a float32 .npy array of shape (3, #P), atomically.
void write_mode(const std::string& path, const cloth::Matrix3X& mode);

/// The fields of a row as written to stability.csv (infinite or NaN numbers empty).
std::vector<std::string> stability_fields(const StabilityRow& row);

/// A row of an earlier sweep's stability.csv (resumed = true); throws UserError naming the
/// file, line and column of a malformed field.
StabilityRow stability_row(const CsvRecord& record);

/// What stability_scenario.toml holds: the options that change a row, then the scenario.
std::string stability_sidecar_text(const Scenario& sc, const StabilityOptions& o);

/// Throws UserError unless the folder dir (ending in '/') holds no earlier sweep or one that
/// ran this scenario with these options.
void check_stability_resumable(const std::string& dir, const Scenario& sc,
                               const StabilityOptions& o);

}  // namespace clothbench
