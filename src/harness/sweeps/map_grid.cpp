/// @file map_grid.cpp

#include "harness/sweeps/map_grid.hpp"

#include <cmath>
#include <cstdlib>
#include <set>

#include "harness/io/csv_writer.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench {
namespace {

constexpr const char* kParticlesKey = "cloth.particles";
constexpr int kMaxValues = 10000;

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  size_t from = 0;
  for (size_t at = s.find(sep); at != std::string::npos; at = s.find(sep, from)) {
    parts.push_back(s.substr(from, at - from));
    from = at + 1;
  }
  parts.push_back(s.substr(from));
  return parts;
}

/// text as a finite number; throws UserError naming the option otherwise.
double number(const std::string& text, const std::string& option) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw UserError(option + ": '" + text + "' is not a finite number");
  return v;
}

/// The N values of a range "A:B:log:N" or "A:B:lin:N".
std::vector<double> range_values(const std::vector<std::string>& parts, const std::string& option) {
  const double a = number(parts[0], option), b = number(parts[1], option);
  const double n = number(parts[3], option);
  const bool log = parts[2] == "log";
  if (!log && parts[2] != "lin")
    throw UserError(option + ": expected a range A:B:log:N or A:B:lin:N, not '" + parts[2] + "'");
  if (n != std::floor(n) || n < 2 || n > kMaxValues)
    throw UserError(option + ": the number of values " + parts[3] +
                    " is not a whole number from 2 to " + std::to_string(kMaxValues));
  if (log && !(a > 0 && b > 0)) throw UserError(option + ": a log range needs A > 0 and B > 0");
  std::vector<double> values;
  for (int i = 0; i < int(n); ++i) {
    const double f = i / (n - 1);  // 0 at A, 1 at B, exactly
    values.push_back(log ? std::pow(10.0, std::log10(a) + f * (std::log10(b) - std::log10(a)))
                         : a + f * (b - a));
  }
  values.front() = a, values.back() = b;
  return values;
}

/// v as a grid edge for cloth.particles: a whole number >= 2.
std::string particle_edge(double v, const std::string& option) {
  const double n = std::round(v);
  if (n < 2 || n > 1e6)
    throw UserError(option + ": " + format_double(v) +
                    " particles per edge; expected a whole number from 2 to 1000000");
  return std::to_string(static_cast<long>(n));
}

}  // namespace

std::string VariedKey::override_text(size_t i) const {
  if (key == kParticlesKey) return key + "=[" + values[i] + "," + values[i] + "]";
  return key + "=" + values[i];
}

VariedKey parse_varied_key(const std::string& text) {
  const size_t eq = text.find('=');
  const std::string option = "--vary " + text;
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw UserError(option + ": expected KEY=V1,V2,... or KEY=A:B:log:N");
  VariedKey k{text.substr(0, eq), {}};
  const std::string spec = text.substr(eq + 1);
  const std::vector<std::string> parts = split(spec, ':');
  const bool particles = k.key == kParticlesKey;
  if (parts.size() == 4) {
    for (double v : range_values(parts, option))
      k.values.push_back(particles ? particle_edge(v, option) : format_double(v));
  } else if (parts.size() == 1) {
    for (const std::string& v : split(spec, ',')) {
      if (particles && number(v, option) != std::round(number(v, option)))
        throw UserError(option + ": " + v + " particles per edge is not a whole number");
      k.values.push_back(particles ? particle_edge(number(v, option), option) : v);
    }
  } else {
    throw UserError(option + ": expected a list V1,V2,... or a range A:B:log:N");
  }
  std::set<std::string> seen;
  for (const std::string& v : k.values)
    if (v.empty() || !seen.insert(v).second)
      throw UserError(option + ": the value '" + v + "' is " +
                      (v.empty() ? "empty" : "given twice"));
  return k;
}

std::vector<GridPoint> grid_points(const std::vector<VariedKey>& keys) {
  std::vector<GridPoint> points = {GridPoint()};
  for (const VariedKey& k : keys) {
    std::vector<GridPoint> next;
    for (const GridPoint& p : points)
      for (size_t i = 0; i < k.values.size(); ++i) {
        next.push_back(p);
        next.back().push_back(i);
      }
    points = next;
  }
  return points;
}

}  // namespace clothbench
