/// @file gate_report.cpp
/// JUnit XML and JSON renderings of the gate table.

#include "harness/gate/gate_report.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "format/number_format.hpp"
#include "harness/io/csv_writer.hpp"

namespace clothbench {
namespace {

/// s with the five XML special characters escaped, and control characters other than tab
/// and newline (not allowed in XML 1.0) replaced by '?'.
std::string xml_escaped(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') ? '?' : c;
    }
  }
  return out;
}

/// s as a JSON string literal.
std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      out += b;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string json_number(double v) {
  return std::isfinite(v) ? format_double(v) : "null";
}

std::string short_number(double v) {
  return cloth::significant(v, 6);
}

/// What a failed gate's <failure> says: the baseline, the value now and what was allowed.
std::string failure_message(const Gate& g) {
  const std::string allowed = g.allowed_text.empty() ? short_number(g.allowed) : g.allowed_text;
  std::string m = "baseline " + short_number(g.baseline) + ", now " + short_number(g.now) +
                  ", difference " + short_number(g.difference) + ", allowed " + allowed;
  return g.note.empty() ? m : m + ": " + g.note;
}

std::string testcase_xml(const Gate& g) {
  const std::string open = "    <testcase name=\"" + xml_escaped(g.engine + " " + g.quantity) +
                           "\" classname=\"clothbench.check." + xml_escaped(g.scenario) +
                           "\" time=\"0\"";
  if (!g.gated)
    return open + ">\n      <skipped message=\"" + xml_escaped(g.note) + "\"/>\n    </testcase>\n";
  if (g.pass) return open + "/>\n";
  const std::string m = xml_escaped(failure_message(g));
  return open + ">\n      <failure message=\"" + m + "\" type=\"gate\">" + m +
         "</failure>\n    </testcase>\n";
}

struct SuiteCounts {
  long tests = 0, failures = 0, skipped = 0;
};

SuiteCounts count(const std::vector<Gate>& gates, const std::string& scenario) {
  SuiteCounts c;
  for (const Gate& g : gates) {
    if (g.scenario != scenario) continue;
    ++c.tests;
    if (!g.gated)
      ++c.skipped;
    else if (!g.pass)
      ++c.failures;
  }
  return c;
}

std::string counts_xml(const SuiteCounts& c, double seconds) {
  return "tests=\"" + std::to_string(c.tests) + "\" failures=\"" + std::to_string(c.failures) +
         "\" errors=\"0\" skipped=\"" + std::to_string(c.skipped) + "\" time=\"" +
         short_number(seconds) + "\"";
}

}  // namespace

std::string junit_xml(const std::vector<Gate>& gates, const std::vector<ScenarioTiming>& timings) {
  // one suite per scenario, in the order the scenarios were checked
  std::vector<std::string> scenarios;
  for (const ScenarioTiming& t : timings) scenarios.push_back(t.scenario);
  for (const Gate& g : gates) {
    bool known = false;
    for (const std::string& s : scenarios) known = known || s == g.scenario;
    if (!known) scenarios.push_back(g.scenario);
  }
  SuiteCounts all;
  double total = 0;
  std::ostringstream body;
  for (const std::string& s : scenarios) {
    const SuiteCounts c = count(gates, s);
    double seconds = 0;
    for (const ScenarioTiming& t : timings) seconds += t.scenario == s ? t.seconds : 0;
    all.tests += c.tests, all.failures += c.failures, all.skipped += c.skipped, total += seconds;
    body << "  <testsuite name=\"clothbench.check." << xml_escaped(s) << "\" "
         << counts_xml(c, seconds) << ">\n";
    for (const Gate& g : gates)
      if (g.scenario == s) body << testcase_xml(g);
    body << "  </testsuite>\n";
  }
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"clothbench check\" " +
         counts_xml(all, total) + ">\n" + body.str() + "</testsuites>\n";
}

std::string gates_json(const std::vector<Gate>& gates) {
  std::ostringstream o;
  long failed = 0, ungated = 0;
  o << "{\n  \"gates\": [";
  for (size_t i = 0; i < gates.size(); ++i) {
    const Gate& g = gates[i];
    failed += g.gated && !g.pass, ungated += !g.gated;
    o << (i ? ",\n    " : "\n    ") << "{\"scenario\": " << json_string(g.scenario)
      << ", \"engine\": " << json_string(g.engine) << ", \"quantity\": " << json_string(g.quantity)
      << ", \"baseline\": " << json_number(g.baseline) << ", \"now\": " << json_number(g.now)
      << ", \"difference\": " << json_number(g.difference)
      << ", \"allowed\": " << json_number(g.allowed)
      << ", \"allowed_text\": " << json_string(g.allowed_text)
      << ", \"gated\": " << (g.gated ? "true" : "false")
      << ", \"pass\": " << (g.pass ? "true" : "false") << ", \"note\": " << json_string(g.note)
      << "}";
  }
  o << (gates.empty() ? "]" : "\n  ]")
    << ",\n  \"passed\": " << long(gates.size()) - failed - ungated << ",\n  \"failed\": " << failed
    << ",\n  \"not_gated\": " << ungated << "\n}\n";
  return o.str();
}

}  // namespace clothbench
