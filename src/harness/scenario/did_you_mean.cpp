#include "harness/scenario/did_you_mean.hpp"

#include <algorithm>
#include <cctype>
#include <vector>

namespace clothbench {

size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      const size_t substitute = diagonal + (std::tolower(a[i - 1]) != std::tolower(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string near_miss(std::string_view word, const Keys& known) {
  std::string_view best;
  size_t best_distance = std::string_view::npos;
  for (std::string_view k : known) {
    size_t d = edit_distance(word, k);
    // a word that is the start of a longer name is one edit away in spirit
    if (word.size() >= 3 && (k.substr(0, word.size()) == word || word.substr(0, k.size()) == k))
      d = std::min<size_t>(d, 1);
    if (d < best_distance) best = k, best_distance = d;
  }
  const size_t allowed = std::max<size_t>(1, std::min<size_t>(3, (word.size() + 1) / 3));
  if (!best.empty() && best_distance <= allowed)
    return "; did you mean \"" + std::string(best) + "\"?";
  return "";
}

std::string suggest(std::string_view word, const Keys& known) {
  const std::string near = near_miss(word, known);
  return near.empty() ? " (expected one of: " + join(known) + ")" : near;
}

}  // namespace clothbench
