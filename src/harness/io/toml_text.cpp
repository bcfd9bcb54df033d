#include "harness/io/toml_text.hpp"

#include <cstdio>

#include "format/number_format.hpp"

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

namespace {

/// Index just past the string that starts at text[i] (a quote), or text.size() if unclosed.
size_t skip_string(std::string_view text, size_t i, int& line) {
  const char quote = text[i];
  const bool multi = text.substr(i, 3) == std::string(3, quote);
  size_t j = i + (multi ? 3 : 1);
  while (j < text.size()) {
    if (text[j] == '\n') ++line;
    if (quote == '"' && text[j] == '\\') {
      j += 2;
      continue;
    }
    if (multi ? text.substr(j, 3) == std::string(3, quote) : text[j] == quote)
      return j + (multi ? 3 : 1);
    if (!multi && text[j] == '\n') return j;  // an unclosed string: the parser will say so
    ++j;
  }
  return j;
}

}  // namespace

std::optional<std::pair<int, std::string>> toml_structure_problem(std::string_view text) {
  int depth = 0, dots = 0, line = 1;
  for (size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '"' || c == '\'') {
      i = skip_string(text, i, line);
      continue;
    }
    if (c == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
      continue;
    }
    if (c == '\n') ++line;
    if (c == '[' || c == '{') ++depth;
    if (c == ']' || c == '}') depth = depth > 0 ? depth - 1 : 0;
    // a dotted key's parts, counted between the separators that end a key
    dots = c == '.' ? dots + 1 : (c == '=' || c == '\n' || c == ',' || c == ']' ? 0 : dots);
    if (depth > kMaxTomlDepth)
      return std::pair(line, "arrays or inline tables nested more than " +
                                 std::to_string(kMaxTomlDepth) + " deep");
    if (dots >= kMaxTomlDepth)
      return std::pair(line,
                       "a dotted key of more than " + std::to_string(kMaxTomlDepth) + " parts");
    ++i;
  }
  return std::nullopt;
}

}  // namespace clothbench
