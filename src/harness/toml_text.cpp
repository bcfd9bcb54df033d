#include "harness/toml_text.hpp"

#include <cstdio>

#include "cloth/number_format.hpp"

namespace clothbench {

using cloth::toml_double;

std::string toml_string(std::string_view s) {
  std::string out = "\"";
  for (char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (ch) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char esc[8];
          std::snprintf(esc, sizeof esc, "\\u%04x", c);
          out += esc;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

std::string describe(const toml::node& n) {
  if (const auto* s = n.as_string()) return toml_string(s->get());
  if (const auto* i = n.as_integer()) return std::to_string(i->get());
  if (const auto* f = n.as_floating_point()) return toml_double(f->get());
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* a = n.as_array()) {
    std::string out = "[";
    for (size_t k = 0; k < a->size(); ++k) {
      if (k == 6) {
        out += ", ...";
        break;
      }
      out += (k ? ", " : "") + describe(*a->get(k));
    }
    return out + "]";
  }
  if (n.is_table()) return "a table";
  return "a date or time";
}

}  // namespace clothbench
