#pragma once
/// @file accuracy_files.hpp
/// The files of an accuracy sweep (see accuracy_sweep.hpp for their columns): typed rows to
/// CSV fields and back (for --resume), and the small tables written whole at the end.

#include <map>
#include <string>
#include <vector>

#include "harness/io/csv_reader.hpp"
#include "harness/sweeps/accuracy_rows.hpp"

namespace clothbench {

/// The columns of work_precision.csv.
const std::vector<std::string>& work_precision_header();
/// The columns of resolution.csv.
const std::vector<std::string>& resolution_header();

/// A row of the time-step study as written to work_precision.csv.
std::vector<std::string> work_precision_fields(const AccuracyRow& r);
/// A row of the resolution study as written to resolution.csv.
std::vector<std::string> resolution_fields(const AccuracyRow& r);
/// A row of an earlier work_precision.csv, on a grid of particles; throws UserError naming
/// the file, line and column of a malformed field.
AccuracyRow work_precision_row(const CsvRecord& record, int particles);
/// A row of an earlier resolution.csv; throws UserError for a malformed field.
AccuracyRow resolution_row(const CsvRecord& record);

/// Writes reference.csv: one row per reference, with the overrides that rerun it.
void write_references(const std::string& path, const std::vector<AccuracyReference>& refs,
                      const std::vector<std::string>& reruns);

/// The rows of an earlier reference.csv, by study (empty when there is none).
std::map<std::string, CsvRecord> read_references(const std::string& path);

/// Throws UserError when an earlier sweep in the folder measured against another reference
/// of ref's study (earlier as read_references gives it, from path).
void check_resumable_reference(const std::string& path,
                               const std::map<std::string, CsvRecord>& earlier,
                               const AccuracyReference& ref);

/// Writes convergence.csv.
void write_convergence(const std::string& path, const std::vector<ConvergenceFit>& fits);

/// Writes recommendation.csv (the time-step study).
void write_recommendations(const std::string& path, const std::vector<Recommendation>& recs,
                           double tolerance);

/// Writes resolution_recommendation.csv.
void write_resolution_recommendations(const std::string& path,
                                      const std::vector<Recommendation>& recs, double tolerance);

}  // namespace clothbench
