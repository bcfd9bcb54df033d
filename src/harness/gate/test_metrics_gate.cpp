#include "harness/gate/test_metrics_gate.hpp"

#include <cmath>

#include "harness/io/csv_reader.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench {

std::vector<Gate> gate_test_metrics(const std::string& scenario, const TestValues& baseline,
                                    const TestValues& now, const Tolerances& tolerances,
                                    bool ensembles_ran) {
  std::vector<Gate> gates;
  auto fail = [&](const std::string& engine, const std::string& q, double b, double v,
                  const std::string& why) {
    gates.push_back({scenario, engine, q, b, v, NAN, 0, false, why, ""});
  };
  // engines on one side only
  for (const auto& [engine, rows] : baseline)
    if (!now.count(engine))
      fail(engine, "test metrics", double(rows.size()), 0,
           "recorded in the baseline's tests.csv but did not run");
  for (const auto& [engine, rows] : now)
    if (!baseline.count(engine))
      fail(engine, "test metrics", 0, double(rows.size()),
           "ran but has no rows in the baseline's tests.csv (record them with --update)");
  for (const auto& [engine, rows] : now) {
    const auto base = baseline.find(engine);
    if (base == baseline.end()) continue;
    // metrics recorded but no longer measured
    for (const auto& [metric, b] : base->second)
      if (!rows.count(metric))
        fail(engine, "test." + metric, b, NAN, "recorded in the baseline but not measured");
    for (const auto& [metric, v] : rows) {
      const std::string q = "test." + metric;
      const auto it = base->second.find(metric);
      const auto tol = tolerances.tests.find(metric);
      if (it == base->second.end()) {
        fail(engine, q, NAN, v, "not in the baseline (record it with --update)");
        continue;
      }
      const double b = it->second;
      // listed as not gated for this engine: shown with the reason
      const auto listed = tolerances.ungated.find(engine);
      if (listed != tolerances.ungated.end() && listed->second.count(q)) {
        gates.push_back({scenario, engine, q, b, v, std::abs(v - b), NAN, true,
                         "not gated: " + listed->second.at(q), "-", false});
        continue;
      }
      // gated by the engine's ensemble: its gate is the ensemble's, or it did not run
      const auto ensemble = tolerances.ensemble.find(engine);
      if (ensemble != tolerances.ensemble.end() && ensemble->second.quantities.count(q)) {
        if (!ensembles_ran)
          gates.push_back({scenario, engine, q, b, v, std::abs(v - b), NAN, true,
                           kEnsembleElsewhere, "-", false});
        continue;
      }
      if (tol == tolerances.tests.end()) {
        fail(engine, q, b, v, "no tolerance for " + metric + " in tolerances.toml [tests]");
        continue;
      }
      const double allowed = tol->second.allowed(b), d = std::abs(v - b);
      Gate g{scenario, engine, q, b, v, d, allowed, true, "", ""};
      // undefined on both sides is the same result; on one side it is a change
      g.pass = (std::isnan(b) && std::isnan(v)) || d <= allowed;
      if (!g.pass) g.note = std::isnan(d) ? "one side is undefined (empty)" : "moved";
      gates.push_back(g);
    }
  }
  return gates;
}

TestValues read_test_values(const std::filesystem::path& p) {
  TestValues values;
  std::map<std::string, long> line_of;
  for (const CsvRecord& r : read_csv(p.string(), output_header("baselines/tests.csv")).records) {
    const std::string key = r.text(0) + "," + r.text(1);
    if (line_of.count(key))
      throw UserError(p.string() + ":" + std::to_string(r.line()) + ": a second row for " + key +
                      " (the first is line " + std::to_string(line_of[key]) +
                      "); restore the file or record it again with check --update");
    line_of[key] = long(r.line());
    values[r.text(0)][r.text(1)] = r.number(2, NAN);
  }
  return values;
}

void write_test_values(const TestValues& values, CsvWriter& out) {
  for (const auto& [engine, rows] : values)
    for (const auto& [metric, v] : rows) {
      out.add(engine).add(metric);
      // undefined: empty, as tests.csv has it
      if (std::isnan(v))
        out.skip();
      else
        out.add(v);
      out.end_row();
    }
}

}  // namespace clothbench
