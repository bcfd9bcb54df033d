#include "harness/fabric/standard_overhang.hpp"

#include <algorithm>
#include <cmath>

#include "cloth/model/constants.hpp"
#include "harness/fabric/elastica.hpp"

namespace clothbench {

namespace {

using cloth::kPi;

/// The index of the candidate overhang nearest l (m).
long nearest(const std::vector<double>& overhangs, double l) {
  const auto it = std::lower_bound(overhangs.begin(), overhangs.end(), l);
  long k = long(it - overhangs.begin());
  if (k == long(overhangs.size()) || (k > 0 && l - overhangs[size_t(k - 1)] < *it - l)) --k;
  return k;
}

/// The elastica's guess of the standard's overhang from one settled run: l = 2 c, with c the
/// bending length its chord angle gives at its overhang; NaN outside the elastica's range.
double elastica_guess(const OverhangRun& run) {
  const double theta = run.chord_angle * kPi / 180.0;
  if (!(theta > 0) || !(theta < 0.99 * elastica_chord_angle(kMaxElasticaLambda))) return NAN;
  return 2.0 * elastica_bending_length(run.overhang, theta);
}

}  // namespace

OverhangSequence find_standard_overhang(const std::vector<double>& overhangs, std::size_t first,
                                        const SettleAt& settle) {
  OverhangSequence out;
  out.overhang = out.bending_length = NAN;
  const long n = long(overhangs.size());
  // lo: longest overhang found below 41.5 degrees, hi: shortest found at or above (-1, n: none)
  long lo = -1, hi = n;
  std::vector<long> run_of(size_t(n), -1);
  long k = std::min(long(first), n - 1);
  while (n > 0) {
    out.runs.push_back(settle(size_t(k)));
    run_of[size_t(k)] = long(out.runs.size()) - 1;
    const double theta = out.runs.back().chord_angle;
    // a run that blew up says nothing about its chord angle
    if (!std::isfinite(theta)) return out;
    if (theta < kStandardChordAngle)
      lo = std::max(lo, k);
    else
      hi = std::min(hi, k);
    if (hi - lo <= 1) break;
    // bracketed: the secant between its ends; else the elastica's guess from the nearer end
    double l = NAN;
    if (lo >= 0 && hi < n) {
      const OverhangRun &a = out.runs[size_t(run_of[size_t(lo)])],
                        &b = out.runs[size_t(run_of[size_t(hi)])];
      l = a.overhang + (kStandardChordAngle - a.chord_angle) / (b.chord_angle - a.chord_angle) *
                           (b.overhang - a.overhang);
    } else {
      l = elastica_guess(out.runs[size_t(run_of[size_t(lo >= 0 ? lo : hi)])]);
    }
    // bisection when the guess fails; always strictly inside the bracket
    const long next = std::isfinite(l) ? nearest(overhangs, l) : lo + (hi - lo) / 2;
    k = std::clamp(next, lo + 1, hi - 1);
  }
  if (lo < 0 || hi >= n) return out;
  OverhangRun &a = out.runs[size_t(run_of[size_t(lo)])], &b = out.runs[size_t(run_of[size_t(hi)])];
  a.bracket = b.bracket = true;
  if (!a.settled || !b.settled) return out;
  // the chord angle linear in the overhang between the two settled runs
  out.overhang = a.overhang + (kStandardChordAngle - a.chord_angle) /
                                  (b.chord_angle - a.chord_angle) * (b.overhang - a.overhang);
  out.bending_length = 0.5 * out.overhang;
  return out;
}

std::vector<TestMetric> standard_rows(const OverhangSequence& q) {
  return {{"standard_overhang", q.overhang, "m"},
          {"bending_length_standard", q.bending_length, "m"},
          {"standard_settles", double(q.runs.size()), "count"}};
}

}  // namespace clothbench
