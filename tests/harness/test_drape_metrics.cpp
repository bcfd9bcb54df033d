// The Cusick drape test's outline metrics on shapes built by hand: fluted disks whose number of
// folds and radii are known, and sequences whose local maxima are counted by eye.

#include <catch2/catch.hpp>
#include <cmath>

#include "harness/fabric/drape_metrics.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A disk of radius 0.15 m in the xz plane at height 0.5 m, rings x spokes, whose rim's radius
/// around the y axis is 0.15 (1 + amplitude cos(folds phi)); the rim hangs 5 cm lower where it
/// is pulled in, as a draped specimen's does.
struct Fluted {
  cloth::Matrix3X x;
  std::vector<cloth::Triangle> triangles;
};

Fluted fluted_disk(int folds, double amplitude, int rings = 12, int spokes = 96) {
  Fluted f;
  f.x.resize(3, 1 + rings * spokes);
  f.x.col(0) = cloth::Vector3(0, 0.5, 0);
  auto index = [&](int ring, int spoke) { return 1 + (ring - 1) * spokes + (spoke % spokes); };
  for (int i = 1; i <= rings; ++i)
    for (int j = 0; j < spokes; ++j) {
      const double phi = 2 * kPi * j / spokes, s = double(i) / rings;
      const double wave = std::cos(folds * phi);
      const double r = 0.15 * s * (1 + amplitude * s * s * wave);
      f.x.col(index(i, j)) =
          cloth::Vector3(r * std::cos(phi), 0.5 - 0.05 * s * s * (1 - wave), r * std::sin(phi));
    }
  for (int j = 0; j < spokes; ++j) f.triangles.push_back({0, index(1, j), index(1, j + 1)});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < spokes; ++j) {
      f.triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      f.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  return f;
}

const cloth::Vector3 kGravity(0, -9.8, 0);
const cloth::Vector3 kAxis(0, 0.5, 0);

}  // namespace

TEST_CASE("local maxima of a circular sequence are counted once each", "[drape]") {
  CHECK(clothbench::count_local_maxima({1, 1, 1, 1}) == 0);
  CHECK(clothbench::count_local_maxima({0, 1, 0, 0}) == 1);
  CHECK(clothbench::count_local_maxima({0, 1, 1, 1, 0}) == 1);       // a plateau
  CHECK(clothbench::count_local_maxima({3, 1, 2, 1, 2}) == 2);       // the last 2 rises on to the 3
  CHECK(clothbench::count_local_maxima({3, 1, 2, 1, 2}, 1.5) == 1);  // only the 3 stands 1.5 up
  CHECK(clothbench::count_local_maxima({2, 0, 2, 1.9, 2, 0}, 0.5) == 2);  // a dip of 0.1: one
  CHECK(clothbench::count_local_maxima({2, 2, 0, 1, 0, 2}) == 2);  // a plateau across the wrap
  CHECK(clothbench::count_local_maxima({0, 1, 2, 3, 4}) == 1);     // one rise, one drop at the wrap
}

TEST_CASE("a flat disk's outline is its radius all round and has no folds", "[drape]") {
  const Fluted f = fluted_disk(6, 0.0);
  const clothbench::DrapeProfile p = clothbench::drape_profile(f.x, f.triangles, kAxis, kGravity);
  REQUIRE(p.radius.size() == size_t(clothbench::kDrapeProfileBins));
  // between two rim vertices the outline is a chord: its radius dips to R cos(pi / spokes)
  for (double r : p.radius) {
    CHECK(r <= 0.15 * (1 + 1e-12));
    CHECK(r >= 0.15 * std::cos(kPi / 96) * (1 - 1e-12));
  }
  CHECK(clothbench::drape_folds(p) == 0);
  // without a prominence the chords' ripple shows through the 10 degree average
  CHECK(clothbench::count_local_maxima(clothbench::smoothed_profile(p.radius, 10)) > 6);
}

TEST_CASE("a fluted disk has as many folds as its outline has lobes", "[drape]") {
  for (int folds : {4, 6, 7, 9, 12}) {
    const Fluted f = fluted_disk(folds, 0.2);
    const clothbench::DrapeProfile p = clothbench::drape_profile(f.x, f.triangles, kAxis, kGravity);
    INFO("folds " << folds);
    CHECK(clothbench::drape_folds(p) == folds);
    // the lobes' tips and troughs: 0.15 (1 +- 0.2), smoothed over 10 degrees the tips come down
    // by 1 - sinc; for 12 lobes a 10 degree box keeps sin(60 deg) / (pi / 3) = 0.83 of the wave
    const std::vector<double> smooth = clothbench::smoothed_profile(p.radius, 10);
    const double top = *std::max_element(smooth.begin(), smooth.end());
    const double half_arc = 5.0 * kPi / 180 * folds;
    CHECK(top == Approx(0.15 * (1 + 0.2 * std::sin(half_arc) / half_arc)).epsilon(0.01));
  }
}

TEST_CASE("the outline is measured around the given axis, along gravity", "[drape]") {
  // the same disk shifted sideways and seen with gravity along z instead of y
  Fluted f = fluted_disk(5, 0.2);
  const cloth::Vector3 shift(0.3, 0, -0.2);
  f.x.colwise() += shift;
  const clothbench::DrapeProfile p =
      clothbench::drape_profile(f.x, f.triangles, kAxis + shift, kGravity);
  CHECK(clothbench::drape_folds(p) == 5);
  // seen along x, the disk in the xz plane is a segment: no area, no lobes to count
  const clothbench::DrapeProfile side =
      clothbench::drape_profile(f.x, f.triangles, kAxis + shift, cloth::Vector3(-9.8, 0, 0));
  CHECK(clothbench::drape_folds(side) == 2);  // a segment's two ends
  CHECK_THROWS(clothbench::drape_profile(f.x, f.triangles, kAxis, cloth::Vector3::Zero()));
}

TEST_CASE("tests.csv rows of a drape name every metric with its unit", "[drape]") {
  const Fluted f = fluted_disk(8, 0.2);
  const auto rows =
      clothbench::drape_rows(clothbench::drape_profile(f.x, f.triangles, kAxis, kGravity), 0.6);
  REQUIRE(rows.size() == 4);
  CHECK(rows[0].metric == "drape_coefficient");
  CHECK(rows[0].value == 0.6);
  CHECK(rows[1].metric == "folds");
  CHECK(rows[1].value == 8);
  CHECK(rows[2].metric == "min_radius");
  CHECK(rows[3].metric == "max_radius");
  CHECK(rows[2].value < rows[3].value);
  CHECK(rows[3].unit == "m");
}
