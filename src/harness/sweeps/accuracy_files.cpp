#include "harness/sweeps/accuracy_files.hpp"

#include <cmath>
#include <limits>

#include "cloth/model/constants.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/io/user_error.hpp"
#include "harness/sweeps/accuracy_recommendation.hpp"

namespace clothbench {

namespace {

using cloth::kInf;
using cloth::kNaN;

std::string optional_double(double v) {
  return std::isfinite(v) ? format_double(v) : "";
}

/// A stable flag as written: "1" or "0".
bool stable_flag(const CsvRecord& record, size_t column) {
  return record.text(column) == "1";
}

}  // namespace

const std::vector<std::string>& work_precision_header() {
  static const std::vector<std::string> header = output_header("work_precision.csv");
  return header;
}

const std::vector<std::string>& resolution_header() {
  static const std::vector<std::string> header = output_header("resolution.csv");
  return header;
}

std::vector<std::string> work_precision_fields(const AccuracyRow& r) {
  return {r.engine,
          r.integrator,
          format_double(r.dt),
          r.stable ? "1" : "0",
          optional_double(r.error_final),
          optional_double(r.error_max),
          format_double(r.wall_s),
          format_double(r.wall_s_per_sim_s),
          std::to_string(r.force_evals),
          std::to_string(r.cg_iterations),
          r.rerun};
}

std::vector<std::string> resolution_fields(const AccuracyRow& r) {
  return {r.engine,
          r.integrator,
          std::to_string(r.particles),
          format_double(r.dt),
          r.stable ? "1" : "0",
          optional_double(r.error_final),
          format_double(r.wall_s_per_sim_s),
          std::to_string(r.force_evals),
          std::to_string(r.cg_iterations),
          r.rerun};
}

AccuracyRow work_precision_row(const CsvRecord& f, int particles) {
  AccuracyRow r;
  r.engine = f.text(0);
  r.integrator = f.text(1);
  r.particles = particles;
  r.dt = f.number(2, kNaN);
  r.stable = stable_flag(f, 3);
  r.error_final = f.number(4, kInf);
  r.error_max = f.number(5, kInf);
  r.wall_s = f.number(6, kNaN);
  r.wall_s_per_sim_s = f.number(7, kNaN);
  r.force_evals = f.integer(8);
  r.cg_iterations = f.integer(9);
  r.rerun = f.text(10);
  return r;
}

AccuracyRow resolution_row(const CsvRecord& f) {
  AccuracyRow r;
  r.engine = f.text(0);
  r.integrator = f.text(1);
  r.particles = static_cast<int>(f.integer(2));
  r.dt = f.number(3, kNaN);
  r.stable = stable_flag(f, 4);
  r.error_final = f.number(5, kInf);
  r.error_max = kNaN;
  r.wall_s_per_sim_s = f.number(6, kNaN);
  r.force_evals = f.integer(7);
  r.cg_iterations = f.integer(8);
  r.rerun = f.text(9);
  if (r.rerun.size() >= 2 && r.rerun.front() == '"')
    r.rerun = r.rerun.substr(1, r.rerun.size() - 2);
  return r;
}

void write_references(const std::string& path, const std::vector<AccuracyReference>& refs,
                      const std::vector<std::string>& reruns) {
  CsvWriter w(path, output_header("reference.csv"));
  for (size_t i = 0; i < refs.size(); ++i) {
    const AccuracyReference& r = refs[i];
    w.add(r.study).add(r.engine).add(std::string("rk4")).add(r.dt).add(r.nu * r.nv);
    w.add(optional_double(r.error_floor)).add(csv_field(reruns[i]));
    w.end_row();
  }
  w.commit();
}

std::map<std::string, CsvRecord> read_references(const std::string& path) {
  std::map<std::string, CsvRecord> out;
  for (const CsvRecord& r : read_csv_leniently(path).records)
    if (r.size() >= 6) out.insert_or_assign(r.text(0), r);
  return out;
}

void check_resumable_reference(const std::string& path,
                               const std::map<std::string, CsvRecord>& earlier,
                               const AccuracyReference& ref) {
  auto it = earlier.find(ref.study);
  if (it == earlier.end()) return;
  const std::vector<std::string>& f = it->second.fields();
  const std::string particles = std::to_string(ref.nu * ref.nv);
  if (f[1] != ref.engine || f[3] != format_double(ref.dt) || f[4] != particles)
    throw UserError(path + ": cannot resume: the earlier sweep's " + ref.study + " reference was " +
                    f[1] + " rk4 at dt = " + f[3] + " s on " + f[4] + " particles, this one is " +
                    ref.engine + " rk4 at dt = " + format_double(ref.dt) + " s on " + particles +
                    " particles (the swept time steps or resolutions changed); run "
                    "without --resume or choose another output folder");
}

void write_convergence(const std::string& path, const std::vector<ConvergenceFit>& fits) {
  CsvWriter w(path, output_header("convergence.csv"));
  for (const ConvergenceFit& fit : fits)
    w.add(fit.engine).add(fit.integrator).add(optional_double(fit.order)).add(fit.points).end_row();
  w.commit();
}

void write_recommendations(const std::string& path, const std::vector<Recommendation>& recs,
                           double tolerance) {
  CsvWriter w(path, output_header("recommendation.csv"));
  for (const Recommendation& r : recs) {
    w.add(r.scope).add(r.engine);
    if (r.found)
      w.add(r.row.integrator).add(r.row.dt).add(r.row.error_max).add(r.row.wall_s_per_sim_s);
    else
      w.skip().skip().skip().skip();
    w.add(tolerance).add(optional_double(r.found ? counted_work(r.row) : kNaN)).end_row();
  }
  w.commit();
}

void write_resolution_recommendations(const std::string& path,
                                      const std::vector<Recommendation>& recs, double tolerance) {
  CsvWriter w(path, output_header("resolution_recommendation.csv"));
  for (const Recommendation& r : recs) {
    w.add(r.scope).add(r.engine);
    if (r.found)
      w.add(r.row.integrator)
          .add(r.row.particles)
          .add(r.row.dt)
          .add(r.row.error_final)
          .add(r.row.wall_s_per_sim_s);
    else
      w.skip().skip().skip().skip().skip();
    w.add(tolerance).add(optional_double(r.found ? counted_work(r.row) : kNaN)).end_row();
  }
  w.commit();
}

}  // namespace clothbench
