#include "format/number_format.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace cloth {

std::string shortest_decimal(double x) {
  char buf[512];
  const double a = std::abs(x);
  const auto format =
      a == 0 || (a >= 1e-5 && a < 1e16) ? std::chars_format::fixed : std::chars_format::scientific;
  const auto r = std::to_chars(buf, buf + sizeof buf, x, format);
  return std::string(buf, r.ptr);
}

std::string toml_double(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::string s = shortest_decimal(x);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string significant(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

}  // namespace cloth
