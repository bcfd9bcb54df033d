#include "harness/gate/ensemble_gate.hpp"

#include <algorithm>
#include <cmath>

#include "format/number_format.hpp"
#include "harness/gate/welch_test.hpp"
#include "harness/io/csv_reader.hpp"
#include "harness/io/csv_writer.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench {

namespace {

bool all_nan(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isnan(x); });
}

}  // namespace

std::string note_number(double v) {
  return cloth::significant(v, 4);
}

Gate ensemble_gate(const std::string& scenario, const std::string& engine,
                   const std::string& quantity, const std::vector<double>& base,
                   const std::vector<double>& now, double alpha) {
  Gate g{scenario, engine, quantity, NAN, NAN, NAN, NAN, true, "", "p >= " + note_number(alpha)};
  if (base.size() < 2 || now.size() < 2) {
    g.pass = false;
    g.note = "ensemble of " + std::to_string(base.size()) + " recorded and " +
             std::to_string(now.size()) + " run members (2 or more each; record with --update)";
    return g;
  }
  // a quantity undefined in every member on both sides (no reference, no support) passes
  if (all_nan(base) && all_nan(now)) {
    g.note = "ensemble: undefined on both sides";
    return g;
  }
  const WelchResult w = welch_test(base, now);
  g.baseline = w.mean_a, g.now = w.mean_b, g.difference = std::abs(w.mean_b - w.mean_a);
  g.pass = w.p >= alpha;
  g.note = std::isnan(w.p) ? "ensemble: a member's value is not finite"
                           : "ensemble of " + std::to_string(base.size()) + "/" +
                                 std::to_string(now.size()) + ": mean " + note_number(w.mean_a) +
                                 " -> " + note_number(w.mean_b) + ", sd " + note_number(w.sd_a) +
                                 " / " + note_number(w.sd_b) + ", t = " + note_number(w.t) + " (" +
                                 note_number(w.dof) + " dof), p = " + note_number(w.p);
  return g;
}

double growth_exponent(const cloth::Matrix3X& x_start_a, const cloth::Matrix3X& x_start_b,
                       const cloth::Matrix3X& x_end_a, const cloth::Matrix3X& x_end_b,
                       double t_end) {
  const double d0 = (x_start_b - x_start_a).norm(), d1 = (x_end_b - x_end_a).norm();
  if (!(t_end > 0) || d1 == 0) return NAN;
  if (d0 == 0) return INFINITY;
  return std::log(d1 / d0) / t_end;
}

EnsembleValues read_ensemble(const std::string& path) {
  EnsembleValues values;
  for (const CsvRecord& r :
       read_csv(path, output_header("baselines/metrics_ensemble.csv")).records) {
    std::vector<double>& v = values[r.text(0) + "/" + r.text(1)];
    const double member = r.number(2, NAN);
    if (!(member == double(v.size())))
      throw UserError(path + ":" + std::to_string(r.line()) + ": member " + r.text(2) +
                      " where member " + std::to_string(v.size()) + " of " + r.text(0) + "/" +
                      r.text(1) + " comes next");
    v.push_back(r.number(3, NAN));
  }
  return values;
}

void write_ensemble(const EnsembleValues& values, CsvWriter& w) {
  for (const auto& [key, v] : values) {
    const size_t slash = key.rfind('/');
    for (size_t m = 0; m < v.size(); ++m)
      w.add(key.substr(0, slash)).add(key.substr(slash + 1)).add(int(m)).add(v[m]).end_row();
  }
}

}  // namespace clothbench
