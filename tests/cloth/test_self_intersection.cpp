#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "cloth/analysis/element_distance.hpp"
#include "cloth/analysis/exact_orient.hpp"
#include "cloth/analysis/self_intersection.hpp"
#include "cloth/model/model.hpp"
#include "mesh_brute_force.hpp"
#include "tolerances.hpp"

using namespace cloth;
using clothbench::test::edge_crosses;
using clothbench::test::graph_distances;
using clothbench::test::unique_edges;

namespace {

// ---- independent references ----

__extension__ typedef __int128 Int128;  // GCC's 128-bit integer, exact for the test's determinants

/// The determinant det[b - a, c - a, d - a] of integer points, exactly (|coordinates| <= 2^25:
/// differences <= 2^26, products of three <= 2^78, six of them well inside 2^127).
Int128 exact_det(const std::array<std::int64_t, 12>& p) {
  const Int128 ux = p[3] - p[0], uy = p[4] - p[1], uz = p[5] - p[2];
  const Int128 vx = p[6] - p[0], vy = p[7] - p[1], vz = p[8] - p[2];
  const Int128 wx = p[9] - p[0], wy = p[10] - p[1], wz = p[11] - p[2];
  return ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
}

int sign_of(Int128 v) {
  return v > 0 ? 1 : (v < 0 ? -1 : 0);
}

/// The same determinant evaluated plainly in doubles.
int naive_sign(const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d) {
  const double det = (b - a).dot((c - a).cross(d - a));
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

Vector3 point(const std::array<std::int64_t, 12>& p, int i) {
  return Vector3(double(p[3 * i]), double(p[3 * i + 1]), double(p[3 * i + 2]));
}

/// Uniform double in [lo, hi) from the top 53 bits of the generator.
double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * (double(rng() >> 11) * 0x1p-53);
}

std::int64_t integer(std::mt19937_64& rng, std::int64_t lo, std::int64_t hi) {
  return lo + static_cast<std::int64_t>(rng() % std::uint64_t(hi - lo + 1));
}

/// Every edge against every triangle sharing no vertex with it.
int brute_crossings(const Matrix3X& x, const std::vector<Triangle>& tris) {
  int count = 0;
  for (const auto& [p, q] : unique_edges(tris))
    for (const Triangle& t : tris) {
      if (std::count(t.begin(), t.end(), p) || std::count(t.begin(), t.end(), q)) continue;
      count += edge_crosses(x, p, q, t);
    }
  return count;
}

/// Every vertex-triangle and edge-edge pair more than two rings apart, capped at the cutoff.
double brute_min_distance(const Matrix3X& x, const std::vector<Triangle>& tris, double cutoff) {
  const int n = static_cast<int>(x.cols());
  const auto dist = graph_distances(n, tris);
  double best = cutoff;
  for (int v = 0; v < n; ++v)
    for (const Triangle& t : tris) {
      if (dist[v][t[0]] <= 2 || dist[v][t[1]] <= 2 || dist[v][t[2]] <= 2) continue;
      best =
          std::min(best, point_triangle_distance(x.col(v), x.col(t[0]), x.col(t[1]), x.col(t[2])));
    }
  const auto edges = unique_edges(tris);
  for (std::size_t i = 0; i < edges.size(); ++i)
    for (std::size_t j = i + 1; j < edges.size(); ++j) {
      const auto [p, q] = edges[i];
      const auto [u, w] = edges[j];
      if (dist[p][u] <= 2 || dist[p][w] <= 2 || dist[q][u] <= 2 || dist[q][w] <= 2) continue;
      best = std::min(best, segment_segment_distance(x.col(p), x.col(q), x.col(u), x.col(w)));
    }
  return best;
}

/// An nu by nv grid of spacing s in the plane y = 0 (x along i, z along j).
Matrix3X flat_grid(int nu, int nv, double s) {
  Matrix3X x(3, nu * nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) x.col(j * nu + i) = Vector3(i * s, 0.0, j * s);
  return x;
}

Matrix3X from_points(const std::vector<Vector3>& pts) {
  Matrix3X x(3, static_cast<Eigen::Index>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i) x.col(static_cast<Eigen::Index>(i)) = pts[i];
  return x;
}

int crossings_of(const std::vector<Vector3>& pts, const std::vector<Triangle>& tris,
                 std::vector<int>* crossing = nullptr) {
  const SelfIntersectionMeter meter(static_cast<int>(pts.size()), tris, 1.0);
  return meter.measure(from_points(pts), crossing).crossings;
}

}  // namespace

// ---- orient3d_sign ----

TEST_CASE("orient3d_sign is exact where doubles get the sign wrong", "[selfintersection]") {
  // a = (0.5 + i u, 0.5 + j u, 0) with u = 2^-53 (one ulp of 0.5), b = (12, 12, 0),
  // c = (24, 24, 0), d = (0, 0, 1): ((b - a) x (c - a)) . (d - a) = 12 (j - i) u exactly
  // (expand the z component of the cross product; d - a has z = 1), so the sign is that of j - i
  const Vector3 b(12, 12, 0), c(24, 24, 0), d(0, 0, 1);
  int naive_wrong = 0;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const Vector3 a(0.5 + i * 0x1p-53, 0.5 + j * 0x1p-53, 0.0);
      const int exact = j > i ? 1 : (j < i ? -1 : 0);
      REQUIRE(orient3d_sign(a, b, c, d) == exact);
      REQUIRE(orient3d_sign_wide(a, b, c, d) == exact);
      naive_wrong += naive_sign(a, b, c, d) != exact;
    }
  // the test means something: plain doubles fail on these inputs
  CHECK(naive_wrong > 0);
}

TEST_CASE("orient3d_sign equals the exact integer determinant on random and degenerate points",
          "[selfintersection]") {
  std::mt19937_64 rng(7);
  constexpr std::int64_t kMax = std::int64_t(1) << 25;
  int zeros = 0, naive_wrong = 0;
  for (int n = 0; n < 30000; ++n) {
    std::array<std::int64_t, 12> p{};
    const int kind = n % 3;
    for (int r = 0; r < 9; ++r) p[r] = integer(rng, -kMax / 8, kMax / 8);
    if (kind == 0) {
      // general position
      for (int r = 9; r < 12; ++r) p[r] = integer(rng, -kMax, kMax);
    } else {
      // d = a + i (b - a) + j (c - a): exactly coplanar; kind 2 then moves it by one unit
      const std::int64_t i = integer(rng, -3, 3), j = integer(rng, -3, 3);
      for (int r = 0; r < 3; ++r) p[9 + r] = p[r] + i * (p[3 + r] - p[r]) + j * (p[6 + r] - p[r]);
      if (kind == 2) p[9 + integer(rng, 0, 2)] += integer(rng, 0, 1) ? 1 : -1;
    }
    const int exact = sign_of(exact_det(p));
    const Vector3 a = point(p, 0), b = point(p, 1), c = point(p, 2), d = point(p, 3);
    REQUIRE(orient3d_sign(a, b, c, d) == exact);
    REQUIRE(orient3d_sign_wide(a, b, c, d) == exact);
    // scaling by a power of two keeps the sign: near overflow and far below 1
    const double up = 0x1p900, down = 0x1p-1000;
    REQUIRE(orient3d_sign(a * up, b * up, c * up, d * up) == exact);
    REQUIRE(orient3d_sign(a * down, b * down, c * down, d * down) == exact);
    zeros += exact == 0;
    naive_wrong += naive_sign(a * up, b * up, c * up, d * up) != exact;
  }
  CHECK(zeros > 5000);
  CHECK(naive_wrong > 0);
}

TEST_CASE("orient3d_sign is exact across the whole exponent range", "[selfintersection]") {
  // with a = 0, b = e_x, c = e_y the determinant is d_z, whatever d_x and d_y
  const Vector3 o(0, 0, 0), ex(1, 0, 0), ey(0, 1, 0);
  const double tiny = std::numeric_limits<double>::denorm_min();
  CHECK(orient3d_sign(o, ex, ey, Vector3(0x1p-1000, 0x1p-1000, tiny)) == 1);
  CHECK(orient3d_sign(o, ex, ey, Vector3(0x1p-1000, 0x1p-1000, -tiny)) == -1);
  CHECK(orient3d_sign(o, ex, ey, Vector3(0x1p1000, -0x1p1000, tiny)) == 1);
  CHECK(orient3d_sign(o, ex, ey, Vector3(0x1p1000, -0x1p1000, 0.0)) == 0);
  // the plane x + y + z = X through X e_x, X e_y, X e_z (normal (1, 1, 1) X^2): the point
  // (X/2, X/2, t) lies t above it
  const double big = 0x1p1000;
  const Vector3 a(big, 0, 0), b(0, big, 0), c(0, 0, big);
  CHECK(orient3d_sign(a, b, c, Vector3(big / 2, big / 2, 0.0)) == 0);
  CHECK(orient3d_sign(a, b, c, Vector3(big / 2, big / 2, tiny)) == 1);
  CHECK(orient3d_sign(a, b, c, Vector3(big / 2, big / 2, -tiny)) == -1);
  const double max = std::numeric_limits<double>::max();
  CHECK(orient3d_sign(Vector3(-max, -max, -max), Vector3(max, -max, -max), Vector3(-max, max, -max),
                      Vector3(-max, -max, max)) == 1);
}

TEST_CASE("orient3d_sign keeps its sign under even permutations and flips under odd ones",
          "[selfintersection]") {
  std::mt19937_64 rng(11);
  for (int n = 0; n < 300; ++n) {
    // near-degenerate points: d in the plane of a, b, c up to rounding
    std::array<Vector3, 4> p;
    for (int i = 0; i < 3; ++i)
      p[i] = Vector3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const double s = uniform(rng, -1, 2), t = uniform(rng, -1, 2);
    p[3] = p[0] + s * (p[1] - p[0]) + t * (p[2] - p[0]);
    const int base = orient3d_sign(p[0], p[1], p[2], p[3]);
    std::array<int, 4> perm{0, 1, 2, 3};
    do {
      // parity by counting inversions
      int inversions = 0;
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) inversions += perm[i] > perm[j];
      const int expected = inversions % 2 == 0 ? base : -base;
      REQUIRE(orient3d_sign(p[perm[0]], p[perm[1]], p[perm[2]], p[perm[3]]) == expected);
    } while (std::next_permutation(perm.begin(), perm.end()));
  }
}

// ---- element distances ----

TEST_CASE("element distances on hand-made and degenerate cases", "[selfintersection]") {
  const Vector3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  // above the interior, beyond a vertex, beside an edge
  CHECK(point_triangle_distance(Vector3(0.5, 0.5, 3), a, b, c) == Approx(3.0));
  CHECK(point_triangle_distance(Vector3(-3, -4, 0), a, b, c) == Approx(5.0));
  CHECK(point_triangle_distance(Vector3(1, -1, 1), a, b, c) == Approx(std::sqrt(2.0)));
  // collapsed triangles: a point, a segment
  CHECK(point_triangle_distance(Vector3(0, 3, 4), a, a, a) == Approx(5.0));
  CHECK(point_triangle_distance(Vector3(1, 1, 0), a, b, Vector3(1, 0, 0)) == Approx(1.0));
  // skew perpendicular segments one apart; parallel overlapping; collinear disjoint; a point
  CHECK(segment_segment_distance(Vector3(-1, 0, 0), Vector3(1, 0, 0), Vector3(0, -1, 1),
                                 Vector3(0, 1, 1)) == Approx(1.0));
  CHECK(segment_segment_distance(a, b, Vector3(1, 1, 0), Vector3(3, 1, 0)) == Approx(1.0));
  CHECK(segment_segment_distance(a, Vector3(1, 0, 0), b, Vector3(3, 0, 0)) == Approx(1.0));
  CHECK(segment_segment_distance(Vector3(1, 2, 0), Vector3(1, 2, 0), a, b) == Approx(2.0));
  CHECK(segment_segment_distance(a, a, a, a) == 0.0);
}

TEST_CASE("element distances bracket densely sampled distances", "[selfintersection]") {
  std::mt19937_64 rng(3);
  const auto random_point = [&] {
    return Vector3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
  };
  constexpr int kSamples = 80;
  for (int n = 0; n < 100; ++n) {
    const Vector3 p = random_point(), a = random_point(), b = random_point(), c = random_point();
    const Vector3 q0 = random_point(), q1 = random_point();
    double tri = 1e300, seg = 1e300;
    for (int i = 0; i <= kSamples; ++i)
      for (int j = 0; j <= kSamples; ++j) {
        const double s = double(i) / kSamples, t = double(j) / kSamples;
        if (i + j <= kSamples) tri = std::min(tri, (p - (a + s * (b - a) + t * (c - a))).norm());
        seg = std::min(seg, ((a + s * (b - a)) - (q0 + t * (q1 - q0))).norm());
      }
    // the sampled value is a real pair's distance (never below the exact one) and within
    // one sample spacing (at most 2 sqrt(3) / kSamples over this box) above it
    const double spacing = 2.0 * std::sqrt(3.0) / kSamples * 2.0;
    const double d_tri = point_triangle_distance(p, a, b, c);
    const double d_seg = segment_segment_distance(a, b, q0, q1);
    CHECK(d_tri <= tri + 1e-12);
    CHECK(tri <= d_tri + spacing);
    CHECK(d_seg <= seg + 1e-12);
    CHECK(seg <= d_seg + spacing);
  }
}

// ---- the meter on hand-made meshes ----

TEST_CASE("crossings of hand-made triangle pairs", "[selfintersection]") {
  const std::vector<Triangle> pair = {{0, 1, 2}, {3, 4, 5}};
  const std::vector<Vector3> t1 = {{-2, 0, -2}, {2, 0, -2}, {0, 0, 2}};
  const auto with = [&](std::vector<Vector3> first, const std::vector<Vector3>& second) {
    first.insert(first.end(), second.begin(), second.end());
    return first;
  };
  SECTION("linked: each triangle's edge through the other's interior: 2") {
    // T2 in the plane x = 0.1 meets y = 0 along z in [0, 10/3]: its edge (3, 4) pierces T1 at
    // (0.1, 0, 0), and T1's edge (1, 2) (x = 0.1 at z = 1.8) pierces T2
    std::vector<int> crossing;
    CHECK(crossings_of(with(t1, {{0.1, -1, 0}, {0.1, 1, 0}, {0.1, 0.5, 5}}), pair, &crossing) == 2);
    CHECK(crossing == std::vector<int>{0, 1});
  }
  SECTION("stabbing: two edges of T2 through T1's interior: 2") {
    // T2's edges from its low vertex cross y = 0 at (0.2, 0, -0.2) and (-0.05, 0, 0.25), both
    // inside T1; T2's part in y = 0 lies inside T1, so no edge of T1 reaches T2
    CHECK(crossings_of(with(t1, {{0.1, -1, 0.1}, {0.3, 1, -0.5}, {-0.2, 1, 0.4}}), pair) == 2);
  }
  const std::vector<Vector3> t0 = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  SECTION("an edge through a triangle's vertex: 0; moved inside: 1") {
    // T2's edge (0,-1,0)-(0,1,0) passes through T1's vertex; T2 meets y = 0 on the segment
    // from (0,0,0) to (-2/3,0,-2/3), outside T1 but for that vertex
    CHECK(crossings_of(with(t0, {{0, -1, 0}, {0, 1, 0}, {-1, 0.5, -1}}), pair) == 0);
    // moved by (0.1, 0, 0.1): the edge pierces T1 at (0.1, 0, 0.1); T1's edges only touch T2
    // at T1's vertex (0, 0, 0)
    CHECK(crossings_of(with(t0, {{0.1, -1, 0.1}, {0.1, 1, 0.1}, {-0.9, 0.5, -0.9}}), pair) == 1);
  }
  SECTION("an edge touching a triangle's edge: 0; moved inside: 2") {
    // T2's edge is the vertical line through (0.5, 0, 0.5), the middle of T1's edge (1, 2)
    CHECK(crossings_of(with(t0, {{0.5, -1, 0.5}, {0.5, 1, 0.5}, {1.5, 0.3, 1.5}}), pair) == 0);
    // moved by (-0.05, 0, -0.05): the edge pierces T1 at (0.45, 0, 0.45), and T1's edge (1, 2)
    // now crosses T2 at (0.5, 0, 0.5)
    CHECK(crossings_of(with(t0, {{0.45, -1, 0.45}, {0.45, 1, 0.45}, {1.45, 0.3, 1.45}}), pair) ==
          2);
  }
  SECTION("coplanar overlapping triangles: 0") {
    CHECK(crossings_of(with(t0, {{0.2, 0, 0.2}, {1.2, 0, 0.2}, {0.2, 0, 1.2}}), pair) == 0);
  }
}

TEST_CASE("a flat grid neither crosses nor comes near itself", "[selfintersection]") {
  const double s = 0.1;
  const SelfIntersectionMeter meter(10 * 10, grid_triangles(10, 10), s);
  const SelfIntersection r = meter.measure(flat_grid(10, 10, s));
  CHECK(r.crossings == 0);
  CHECK(r.complete);
  // elements three rings apart on the grid are at least one spacing apart
  CHECK(r.min_distance == s);
  CHECK(brute_min_distance(flat_grid(10, 10, s), grid_triangles(10, 10), s) == s);
}

namespace {

/// A 5 by 10 grid (x = i, rows j) folded so its upper half passes through its lower half.
/// Rows 0-4 lie flat in y = 0 at z = j. Rows 5-9 are shifted by 0.25 in x and follow the
/// profile (y, z) = (1, 4), (1, 3), (1, 2), (1, 1), (-1, 2): up from the fold row 4, back over
/// the flat half at y = 1, then down through it between rows 8 and 9, whose band lies in the
/// plane y = 1 - 2 (z - 1) and meets y = 0 along z = 1.5, x in [0.25, 4.25].
/// Crossings, all at z = 1.5, in the flat half's cell row 1 (z in [1, 2]):
/// - the band's column edges at x = 0.25, 1.25, 2.25, 3.25 (4.25 is outside the flat half): 4
/// - the band's diagonals at x = 0.75, 1.75, 2.75, 3.75: 4
///   (none on the flat half's diagonals z - 1 = x - i, nor on its columns)
/// - the flat half's column edges at x = 1, 2, 3, 4 (x = 0 is outside the band): 4
/// - the flat half's diagonals at x = 0.5, 1.5, 2.5, 3.5: 4
///   (none on the band's edges at x = i + 0.25, i + 0.75)
/// Total 16. Everything else is at y = 1 or y = -1 or meets y = 0 only in the fold row 4.
Matrix3X folded_grid() {
  const int nu = 5;
  const double profile_y[10] = {0, 0, 0, 0, 0, 1, 1, 1, 1, -1};
  const double profile_z[10] = {0, 1, 2, 3, 4, 4, 3, 2, 1, 2};
  Matrix3X x(3, nu * 10);
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < nu; ++i)
      x.col(j * nu + i) = Vector3(i + (j > 4 ? 0.25 : 0.0), profile_y[j], profile_z[j]);
  return x;
}

}  // namespace

TEST_CASE("a grid folded through itself crosses 16 times", "[selfintersection]") {
  const auto tris = grid_triangles(5, 10);
  const SelfIntersectionMeter meter(50, tris, 1.0);
  std::vector<int> crossing;
  const SelfIntersection r = meter.measure(folded_grid(), &crossing);
  CHECK(r.crossings == 16);
  CHECK(brute_crossings(folded_grid(), tris) == 16);
  // the pierced triangles, which also hold every piercing edge: the flat half's cell row 1
  // (triangles 8-15) and the band between rows 8 and 9 (triangles 64-71)
  std::vector<int> expected;
  for (int t = 8; t < 16; ++t) expected.push_back(t);
  for (int t = 64; t < 72; ++t) expected.push_back(t);
  CHECK(crossing == expected);
  CHECK(r.min_distance == Approx(brute_min_distance(folded_grid(), tris, 1.0))
                              .margin(clothbench::tol::kDistanceRoundoff));
}

TEST_CASE("grid_triangles splits each cell along its (i, j)-(i+1, j+1) diagonal",
          "[selfintersection]") {
  const int nu = 4, nv = 3;
  const auto tris = grid_triangles(nu, nv);
  REQUIRE(tris.size() == 2u * (nu - 1) * (nv - 1));
  int t = 0;
  for (int j = 0; j + 1 < nv; ++j)
    for (int i = 0; i + 1 < nu; ++i) {
      const int p00 = j * nu + i;
      CHECK(tris[t++] == Triangle{p00, p00 + 1, p00 + nu + 1});
      CHECK(tris[t++] == Triangle{p00, p00 + nu + 1, p00 + nu});
    }
  // the first cell's triangles, by hand: (0, 1, 5) and (0, 5, 4)
  CHECK(tris[0] == Triangle{0, 1, 5});
  CHECK(tris[1] == Triangle{0, 5, 4});
  CHECK(grid_triangles(1, 5).empty());
}

// ---- the meter against brute force ----

namespace {

/// A fan of n triangles around vertex 0 (a high-valence vertex: its neighbours' 2-rings are
/// large, so the meter intersects neighbour lists there).
std::vector<Triangle> fan(int n) {
  std::vector<Triangle> tris;
  for (int k = 0; k < n; ++k) tris.push_back({0, 1 + k, 1 + (k + 1) % n});
  return tris;
}

struct RandomMesh {
  Matrix3X x;
  std::vector<Triangle> tris;
  double cutoff;
};

RandomMesh random_mesh(int kind, std::mt19937_64& rng) {
  RandomMesh m;
  if (kind == 0 || kind == 1) {
    // a triangle soup in the unit box over a shared vertex pool; kind 1 on the integer lattice
    // {0, 1, 2}^3 / 2, full of touching and coplanar pairs
    const int n = 45;
    m.x.resize(3, n);
    for (int v = 0; v < n; ++v)
      for (int r = 0; r < 3; ++r)
        m.x(r, v) = kind == 0 ? uniform(rng, 0, 1) : 0.5 * double(integer(rng, 0, 2));
    for (int t = 0; t < 30; ++t) {
      Triangle tri{};
      do {
        for (int& v : tri) v = static_cast<int>(integer(rng, 0, n - 1));
      } while (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]);
      m.tris.push_back(tri);
    }
    m.cutoff = 0.3;
  } else {
    // a crumpled grid (kind 2) or fan (kind 3): rest spacing 0.1, jittered by up to 0.25
    m.tris = kind == 2 ? grid_triangles(8, 8) : fan(300);
    const int n = kind == 2 ? 64 : 301;
    m.x = kind == 2 ? flat_grid(8, 8, 0.1) : Matrix3X::Zero(3, n);
    for (int v = 1; kind == 3 && v < n; ++v)
      m.x.col(v) = Vector3(std::cos(v * 0.0209), 0.0, std::sin(v * 0.0209)) * 0.5;
    for (int v = 0; v < n; ++v)
      for (int r = 0; r < 3; ++r) m.x(r, v) += uniform(rng, -0.25, 0.25);
    m.cutoff = 0.1;
  }
  return m;
}

}  // namespace

TEST_CASE("the meter equals brute force on random meshes", "[selfintersection]") {
  const int kind = GENERATE(0, 1, 2, 3);
  const unsigned seed = GENERATE(1u, 2u, 3u);
  std::mt19937_64 rng(seed * 100 + static_cast<unsigned>(kind));
  const RandomMesh m = random_mesh(kind, rng);
  const SelfIntersectionMeter meter(static_cast<int>(m.x.cols()), m.tris, m.cutoff);
  const SelfIntersection r = meter.measure(m.x);
  INFO("kind " << kind << " seed " << seed);
  REQUIRE(r.complete);
  const int brute = brute_crossings(m.x, m.tris);
  CHECK(r.crossings == brute);
  CHECK(
      r.min_distance ==
      Approx(brute_min_distance(m.x, m.tris, m.cutoff)).margin(clothbench::tol::kDistanceRoundoff));
  // the random soups and crumpled meshes do cross, or the comparison says little
  if (kind != 1) CHECK(brute > 0);
}

TEST_CASE("the 2-ring exclusion equals breadth-first graph distance", "[selfintersection]") {
  const int n = GENERATE(0, 1);
  const auto tris = n == 0 ? grid_triangles(7, 6) : fan(300);
  const int count_v = n == 0 ? 42 : 301;
  const SelfIntersectionMeter meter(count_v, tris, 1.0);
  const auto dist = graph_distances(count_v, tris);
  for (int v = 0; v < count_v; ++v)
    for (int w = 0; w < count_v; ++w) REQUIRE(meter.within_two_rings(v, w) == (dist[v][w] <= 2));
}

// ---- blown-up states ----

TEST_CASE("a state that is not finite gives -1 and NaN", "[selfintersection]") {
  const SelfIntersectionMeter meter(16, grid_triangles(4, 4), 0.1);
  Matrix3X x = flat_grid(4, 4, 0.1);
  x(1, 5) =
      GENERATE(std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity());
  std::vector<int> crossing{1, 2};
  const SelfIntersection r = meter.measure(x, &crossing);
  CHECK(r.crossings == -1);
  CHECK(std::isnan(r.min_distance));
  CHECK(crossing.empty());
}

TEST_CASE("blown-up states are measured in bounded work", "[selfintersection][.heavy]") {
  const int nu = 48;
  const auto tris = grid_triangles(nu, nu);
  const SelfIntersectionMeter meter(nu * nu, tris, 0.01);
  const long long elements = nu * nu + static_cast<long long>(meter.edges().size() + tris.size());
  std::mt19937_64 rng(5);
  SECTION("every vertex at one point: nothing crosses, distance 0, little work") {
    Matrix3X x(3, nu * nu);
    x.colwise() = Vector3(0.3, 0.2, 0.1);
    const SelfIntersection r = meter.measure(x);
    CHECK(r.crossings == 0);
    CHECK(r.min_distance == 0.0);
    CHECK(r.complete);
    CHECK(r.work <= 4 * elements);
  }
  SECTION("huge finite coordinates: finite answers within the budget") {
    Matrix3X x(3, nu * nu);
    for (int v = 0; v < nu * nu; ++v)
      for (int r = 0; r < 3; ++r) x(r, v) = uniform(rng, -1e300, 1e300);
    const SelfIntersection r = meter.measure(x);
    CHECK(r.crossings >= 0);
    CHECK(r.min_distance >= 0.0);
    CHECK(r.min_distance <= 0.01);
    // a query stops within one bucket (at most every triangle) past the budget
    CHECK(r.work <= meter.work_budget() + static_cast<long long>(tris.size()) + kMaxCellsPerBox);
  }
  SECTION("everything inside one cell: the budget stops it and says so") {
    Matrix3X x(3, nu * nu);
    for (int v = 0; v < nu * nu; ++v)
      for (int r = 0; r < 3; ++r) x(r, v) = uniform(rng, 0, 1e-9);
    const SelfIntersection r = meter.measure(x);
    CHECK_FALSE(r.complete);
    CHECK(r.crossings > 0);
    CHECK(r.work <= meter.work_budget() + static_cast<long long>(tris.size()) + kMaxCellsPerBox);
  }
  SECTION(
      "two vertices thrown to +-1e300: the long triangles are checked apart, the rest as usual") {
    Matrix3X x = flat_grid(nu, nu, 0.01);
    x.col(nu + 1) = Vector3(1e300, 3e299, -7e299);
    x.col(30 * nu + 20) = Vector3(-2e299, -1e300, 5e299);
    const SelfIntersection r = meter.measure(x);
    CHECK(r.complete);
    // the flat grid's own work, plus the long triangles against every query and the long
    // edges' queries against every triangle
    const SelfIntersection flat = meter.measure(flat_grid(nu, nu, 0.01));
    CHECK(r.work <= flat.work + 12 * elements + 12 * static_cast<long long>(tris.size()));
  }
}

TEST_CASE("a small blown-up state still equals brute force", "[selfintersection]") {
  std::mt19937_64 rng(9);
  const auto tris = grid_triangles(6, 6);
  Matrix3X x(3, 36);
  const double scale = GENERATE(1e300, 1e-300);
  for (int v = 0; v < 36; ++v)
    for (int r = 0; r < 3; ++r) x(r, v) = uniform(rng, -scale, scale);
  // and one vertex of a very different size
  x.col(14) *= scale > 1 ? 1e-320 : 1e300;
  const SelfIntersectionMeter meter(36, tris, 0.5);
  const SelfIntersection r = meter.measure(x);
  REQUIRE(r.complete);
  CHECK(r.crossings == brute_crossings(x, tris));
  CHECK(r.crossings > 0);
}

TEST_CASE("a flat grid costs a bounded number of work units per element", "[selfintersection]") {
  // a machine-independent cost: cells addressed and bucket entries read. A vertex or edge query
  // looks up at most 27 cells (its box inflated by the cutoff, in cells of twice the spacing)
  // holding a few triangles each; this grid takes 74 units per element (1.8 M), all pairs
  // would take about 2000 (5e7): the bound catches a broad phase that degrades
  const int nu = 64;
  const auto tris = grid_triangles(nu, nu);
  const SelfIntersectionMeter meter(nu * nu, tris, 1.0 / (nu - 1));
  const SelfIntersection r = meter.measure(flat_grid(nu, nu, 1.0 / (nu - 1)));
  const long long elements = nu * nu + static_cast<long long>(meter.edges().size() + tris.size());
  CHECK(r.complete);
  CHECK(r.work <= 100 * elements);
}
