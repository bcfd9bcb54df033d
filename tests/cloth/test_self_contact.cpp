#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "cloth/analysis/element_distance.hpp"
#include "cloth/analysis/self_intersection.hpp"
#include "cloth/contact/self_contact.hpp"
#include "cloth/model/model.hpp"
#include "mesh_brute_force.hpp"
#include "tolerances.hpp"

using namespace cloth;
using clothbench::test::edge_crosses;
using clothbench::test::graph_distances;
using clothbench::test::unique_edges;

namespace {

constexpr double kG = 9.81;  // m/s^2

/// Uniform double in [lo, hi) from the top 53 bits of the generator.
double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * (double(rng() >> 11) * 0x1p-53);
}

/// Appends an nu by nv grid (spacing d, corner at origin, in the plane z = origin.z) to the
/// positions and triangles.
void add_sheet(std::vector<Vector3>& pts, std::vector<Triangle>& tris, int nu, int nv, double d,
               const Vector3& origin) {
  const int base = static_cast<int>(pts.size());
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) pts.push_back(origin + Vector3(i * d, j * d, 0));
  for (Triangle t : grid_triangles(nu, nv)) {
    for (int& v : t) v += base;
    tris.push_back(t);
  }
}

Matrix3X to_matrix(const std::vector<Vector3>& pts) {
  Matrix3X x(3, pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) x.col(static_cast<Eigen::Index>(i)) = pts[i];
  return x;
}

using PairKey = std::pair<int, std::array<int, 4>>;

/// Every vertex-triangle and edge-edge pair more than two rings apart closer than limit, with
/// its distance, by brute force over all pairs.
std::map<PairKey, double> brute_pairs(const Matrix3X& x, const std::vector<Triangle>& tris,
                                      double limit) {
  const int n = static_cast<int>(x.cols());
  const auto dist = graph_distances(n, tris);
  std::map<PairKey, double> out;
  for (int v = 0; v < n; ++v)
    for (const Triangle& t : tris) {
      if (dist[v][t[0]] <= 2 || dist[v][t[1]] <= 2 || dist[v][t[2]] <= 2) continue;
      const double d = point_triangle_distance(x.col(v), x.col(t[0]), x.col(t[1]), x.col(t[2]));
      if (d < limit) out[{0, {v, t[0], t[1], t[2]}}] = d;
    }
  const auto edges = unique_edges(tris);
  for (std::size_t e = 0; e < edges.size(); ++e)
    for (std::size_t f = e + 1; f < edges.size(); ++f) {
      const auto [p, q] = edges[e];
      const auto [r, s] = edges[f];
      if (dist[p][r] <= 2 || dist[p][s] <= 2 || dist[q][r] <= 2 || dist[q][s] <= 2) continue;
      const double d = segment_segment_distance(x.col(p), x.col(q), x.col(r), x.col(s));
      if (d < limit) out[{1, {p, q, r, s}}] = d;
    }
  return out;
}

/// Edge-triangle crossings (the meter's exact rule) between elements more than two rings
/// apart, by brute force.
int far_crossings(const Matrix3X& x, const std::vector<Triangle>& tris) {
  const auto dist = graph_distances(static_cast<int>(x.cols()), tris);
  int count = 0;
  for (const auto& [p, q] : unique_edges(tris))
    for (const Triangle& t : tris) {
      bool near = false;
      for (int k = 0; k < 3; ++k) near = near || dist[p][t[k]] <= 2 || dist[q][t[k]] <= 2;
      if (!near) count += edge_crosses(x, p, q, t);
    }
  return count;
}

Vector3 momentum(const Matrix3X& v, const VectorX& mass) {
  Vector3 p = Vector3::Zero();
  for (Eigen::Index i = 0; i < v.cols(); ++i) p += mass[i] * v.col(i);
  return p;
}

Vector3 angular_momentum(const Matrix3X& x, const Matrix3X& v, const VectorX& mass) {
  Vector3 l = Vector3::Zero();
  for (Eigen::Index i = 0; i < v.cols(); ++i)
    l += mass[i] * Vector3(x.col(i)).cross(Vector3(v.col(i)));
  return l;
}

/// Two 5 by 5 sheets 2 cm apart, offset sideways so vertices lie over triangle interiors,
/// closing at the given relative speed; random masses when a generator is given.
struct TwoSheets {
  std::vector<Triangle> tris;
  Matrix3X x, v;
  VectorX mass, inv_mass;

  TwoSheets(double speed, std::mt19937_64* rng = nullptr) {
    std::vector<Vector3> pts;
    add_sheet(pts, tris, 5, 5, 0.05, Vector3(0, 0, 0));
    add_sheet(pts, tris, 5, 5, 0.05, Vector3(0.013, 0.021, 0.02));
    x = to_matrix(pts);
    const Eigen::Index n = x.cols();
    v = Matrix3X::Zero(3, n);
    mass = VectorX::Constant(n, 0.01);
    for (Eigen::Index i = 0; i < n; ++i) {
      v(2, i) = i < 25 ? 0.5 * speed : -0.5 * speed;
      if (rng) {
        mass[i] = uniform(*rng, 0.005, 0.02);
        v.col(i) += Vector3(uniform(*rng, -1, 1), uniform(*rng, -1, 1), uniform(*rng, -1, 1));
      }
    }
    inv_mass = mass.cwiseInverse();
  }
};

}  // namespace

TEST_CASE("a vertex dropped onto a held triangle comes to rest at the thickness",
          "[self-contact]") {
  // a held triangle in z = 0 and a free vertex 10 cm above its interior
  const std::vector<Triangle> tris = {{0, 1, 2}};
  Matrix3X x(3, 4);
  x.col(0) = Vector3(-1, -1, 0);
  x.col(1) = Vector3(1, -1, 0);
  x.col(2) = Vector3(0, 1, 0);
  x.col(3) = Vector3(0.1, 0.05, 0.1);
  Matrix3X v = Matrix3X::Zero(3, 4);
  const VectorX inv_mass = (VectorX(4) << 0, 0, 0, 100).finished();
  SelfContactParams params;
  SelfContact contact(4, tris, params);
  // at 1 ms the landing vertex enters the contact band; at 10 ms it would jump through it
  const double h = GENERATE(1e-3, 1e-2);
  const int steps = static_cast<int>(std::lround(3.0 / h));
  int proximity_steps = 0, collision_steps = 0;
  // symplectic Euler under gravity for 3 s, the pass after each step
  for (int step = 0; step < steps; ++step) {
    const Matrix3X x_start = x;
    v(2, 3) -= kG * h;
    x.col(3) += h * v.col(3);
    const SelfContactStats stats = contact.resolve(h, x_start, x, v, inv_mass);
    REQUIRE(stats.resolved);
    REQUIRE(x(2, 3) > 0);
    proximity_steps += stats.proximities > 0;
    collision_steps += stats.ccd_collisions > 0;
  }
  CHECK(collision_steps == (h > 5e-3 ? 1 : 0));
  CHECK(proximity_steps > steps / 2);
  // at rest at the repulsion's rest distance, inside the contact band
  CHECK(x(2, 3) == Approx(params.rest_gap * params.thickness)
                       .epsilon(clothbench::tol::kRestAtThicknessRelative));
  CHECK(x(2, 3) < params.thickness);
  CHECK(std::abs(v(2, 3)) < clothbench::tol::kRestVelocity);
  // the held triangle did not move
  CHECK(x.col(0) == Vector3(-1, -1, 0));
}

TEST_CASE("a sheet driven onto a held sheet faster than the thickness per step never crosses it",
          "[self-contact]") {
  const double speed = GENERATE(1.0, 6.0, 20.0);  // m/s
  const double h = 0.01;                          // s: 1 to 20 cm per step against a 2 cm gap
  // a held 7 by 7 sheet and a free 4 by 4 one above its middle, offset so that vertices lie
  // over triangle interiors
  std::vector<Vector3> pts;
  std::vector<Triangle> tris;
  add_sheet(pts, tris, 7, 7, 0.05, Vector3(0, 0, 0));
  add_sheet(pts, tris, 4, 4, 0.05, Vector3(0.063, 0.071, 0.02));
  Matrix3X x = to_matrix(pts);
  const int n = static_cast<int>(x.cols());
  Matrix3X v = Matrix3X::Zero(3, n);
  VectorX inv_mass = VectorX::Zero(n);
  for (int i = 49; i < n; ++i) {
    v(2, i) = -speed;
    inv_mass[i] = 100;
  }
  SelfIntersectionMeter meter(n, tris, 0.05);
  // with collision impulses, or with impact zones alone (zones holding held vertices)
  SelfContactParams params;
  params.ccd_iterations = GENERATE(5, 0);
  SelfContact contact(n, tris, params);
  int collisions = 0;
  for (int step = 0; step < 20; ++step) {
    const Matrix3X x_start = x;
    x += h * v;
    const SelfContactStats stats = contact.resolve(h, x_start, x, v, inv_mass);
    collisions += stats.ccd_collisions;
    REQUIRE(stats.resolved);
    const SelfIntersection m = meter.measure(x);
    REQUIRE(m.complete);
    REQUIRE(m.crossings == 0);
    REQUIRE(m.min_distance > 0);
    // the free sheet stays above the held one, which does not move
    REQUIRE(x.row(2).tail(16).minCoeff() > 0);
    REQUIRE(x.leftCols(49) == x_start.leftCols(49));
  }
  CHECK(collisions > 0);
}

TEST_CASE("two free sheets (particles without springs) driven together never cross",
          "[self-contact]") {
  const double speed = GENERATE(1.0, 6.0, 20.0);  // m/s, relative
  const double h = 0.01;                          // s: 1 to 20 cm per step against a 2 cm gap
  TwoSheets s(speed);
  const int n = static_cast<int>(s.x.cols());
  SelfIntersectionMeter meter(n, s.tris, 0.05);
  SelfContact contact(n, s.tris, SelfContactParams{});
  int collisions = 0;
  for (int step = 0; step < 20; ++step) {
    const Matrix3X x_start = s.x;
    s.x += h * s.v;
    const SelfContactStats stats = contact.resolve(h, x_start, s.x, s.v, s.inv_mass);
    collisions += stats.ccd_collisions;
    REQUIRE(stats.resolved);
    const SelfIntersection m = meter.measure(s.x);
    REQUIRE(m.crossings == 0);
    REQUIRE(m.min_distance > 0);
    REQUIRE(far_crossings(s.x, s.tris) == 0);
  }
  CHECK(collisions > 0);
}

TEST_CASE("two layers in violent random motion end every step crossing free", "[self-contact]") {
  const std::uint64_t seed = GENERATE(21u, 22u, 23u, 24u, 25u);
  std::mt19937_64 rng(seed);
  TwoSheets s(0.0, &rng);
  const int n = static_cast<int>(s.x.cols());
  SelfIntersectionMeter meter(n, s.tris, 0.05);
  // the continuous check on every pair sharing no vertex, or on the two-ring rule's pairs only
  SelfContactParams params;
  params.near_collisions = GENERATE(true, false);
  SelfContact contact(n, s.tris, params);
  const double h = 0.01;  // s: random velocities up to 10 m/s, 10 cm per step, 2 edge lengths
  int zones = 0;
  for (int step = 0; step < 10; ++step) {
    for (int i = 0; i < n; ++i)
      s.v.col(i) = Vector3(uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10));
    const Matrix3X x_start = s.x;
    s.x += h * s.v;
    const SelfContactStats stats = contact.resolve(h, x_start, s.x, s.v, s.inv_mass);
    zones += stats.impact_zones;
    const SelfIntersection m = meter.measure(s.x);
    REQUIRE(m.complete);
    REQUIRE(m.min_distance > 0);
    REQUIRE(far_crossings(s.x, s.tris) == 0);
    if (params.near_collisions) REQUIRE(m.crossings == 0);
    // a pass that gives up keeps every free vertex at its start
    if (!stats.resolved) REQUIRE(s.x == x_start);
  }
  // (the impact zones are exercised: the near pairs' collisions need them here)
  if (params.near_collisions) CHECK(zones > 0);
}

TEST_CASE("the pass is deterministic", "[self-contact]") {
  std::mt19937_64 rng(7);
  TwoSheets a(10.0, &rng);
  TwoSheets b = a;
  const int n = static_cast<int>(a.x.cols());
  SelfContact one(n, a.tris, SelfContactParams{}), two(n, a.tris, SelfContactParams{});
  for (int step = 0; step < 5; ++step) {
    const Matrix3X xa = a.x, xb = b.x;
    a.x += 0.01 * a.v;
    b.x += 0.01 * b.v;
    one.resolve(0.01, xa, a.x, a.v, a.inv_mass);
    two.resolve(0.01, xb, b.x, b.v, b.inv_mass);
    REQUIRE(a.x == b.x);
    REQUIRE(a.v == b.v);
  }
}

TEST_CASE("self-contact conserves linear momentum, and angular momentum in impact zones",
          "[self-contact]") {
  const std::uint64_t seed = GENERATE(1u, 2u, 3u);
  std::mt19937_64 rng(seed);
  TwoSheets s(10.0, &rng);
  const int n = static_cast<int>(s.x.cols());
  const double h = 0.01;
  const Matrix3X x_start = s.x;
  Matrix3X x_end = s.x + h * s.v;
  SECTION("proximity impulses, with friction") {
    SelfContactParams p;
    p.friction = 0.4;
    p.thickness = 0.03;  // thicker than the gap
    SelfContact contact(n, s.tris, p);
    const Vector3 before = momentum(s.v, s.mass);
    const SelfContactStats stats = contact.resolve(h, x_start, x_end, s.v, s.inv_mass);
    CHECK(stats.proximities > 0);
    CHECK(stats.resolved);
    CHECK((momentum(s.v, s.mass) - before).norm() < clothbench::tol::kContactMomentum);
  }
  SECTION("collision impulses and zones, with friction") {
    SelfContactParams p;
    p.friction = 0.4;
    SelfContact contact(n, s.tris, p);
    const Vector3 before = momentum(s.v, s.mass);
    const SelfContactStats stats = contact.resolve(h, x_start, x_end, s.v, s.inv_mass);
    CHECK(stats.proximities == 0);
    CHECK(stats.ccd_collisions > 0);
    CHECK(stats.resolved);
    CHECK((momentum(s.v, s.mass) - before).norm() < clothbench::tol::kContactMomentum);
  }
  SECTION("impact zones alone") {
    SelfContactParams p;
    p.ccd_iterations = 0;  // the collisions go straight to the zones
    SelfContact contact(n, s.tris, p);
    const Vector3 before = momentum(s.v, s.mass);
    const Vector3 l_before = angular_momentum(x_start, s.v, s.mass);
    const SelfContactStats stats = contact.resolve(h, x_start, x_end, s.v, s.inv_mass);
    CHECK(stats.proximities == 0);
    CHECK(stats.impact_zones > 0);
    CHECK(stats.resolved);
    CHECK((momentum(s.v, s.mass) - before).norm() < clothbench::tol::kContactMomentum);
    CHECK((angular_momentum(x_start, s.v, s.mass) - l_before).norm() <
          clothbench::tol::kContactMomentum);
    SelfIntersectionMeter meter(n, s.tris, 0.05);
    CHECK(meter.measure(x_end).crossings == 0);
  }
}

namespace {

/// A vertex resting on a held triangle tilted by theta about the x axis, friction mu, for 500
/// steps of 1 ms: its displacement along the slope (downhill positive).
double slide_on_incline(double theta, double mu) {
  const Vector3 e1(1, 0, 0), e2(0, std::cos(theta), std::sin(theta));
  const Vector3 normal = e1.cross(e2);
  const std::vector<Triangle> tris = {{0, 1, 2}};
  SelfContactParams params;
  params.friction = mu;
  Matrix3X x(3, 4);
  x.col(0) = -5 * e1 - 5 * e2;
  x.col(1) = 5 * e1 - 5 * e2;
  x.col(2) = 5 * e2;
  // at rest at the repulsion's rest distance
  x.col(3) = e2 + params.rest_gap * params.thickness * normal;
  const Vector3 start = x.col(3);
  Matrix3X v = Matrix3X::Zero(3, 4);
  const VectorX inv_mass = (VectorX(4) << 0, 0, 0, 100).finished();
  SelfContact contact(4, tris, params);
  const double h = 1e-3;
  for (int step = 0; step < 500; ++step) {
    const Matrix3X x_start = x;
    v(2, 3) -= kG * h;
    x.col(3) += h * v.col(3);
    REQUIRE(contact.resolve(h, x_start, x, v, inv_mass).resolved);
    REQUIRE((x.col(3) - x.col(0)).dot(normal) > 0);
  }
  // sideways it never moves
  CHECK(std::abs((x.col(3) - start).dot(e1)) < clothbench::tol::kStickDisplacement);
  return -(x.col(3) - start).dot(e2);
}

}  // namespace

TEST_CASE("coulomb friction holds a vertex below the friction angle and lets it slide above",
          "[self-contact]") {
  const double mu = 0.5, h = 1e-3;
  const int steps = 500;
  SECTION("tan theta < mu: held") {
    const double theta = std::atan(mu) - 0.1;
    CHECK(std::abs(slide_on_incline(theta, mu)) < clothbench::tol::kStickDisplacement);
  }
  SECTION("tan theta > mu: slides with g (sin theta - mu cos theta)") {
    const double theta = std::atan(mu) + 0.2;
    const double s = slide_on_incline(theta, mu);
    // symplectic Euler under constant acceleration a: s_N = a h^2 N (N + 1) / 2
    const double a = 2 * s / (h * h * steps * (steps + 1.0));
    CHECK(a == Approx(kG * (std::sin(theta) - mu * std::cos(theta)))
                   .epsilon(clothbench::tol::kSlideAccelerationRelative));
  }
  SECTION("no friction: slides with g sin theta") {
    const double theta = 0.3;
    const double s = slide_on_incline(theta, 0.0);
    const double a = 2 * s / (h * h * steps * (steps + 1.0));
    CHECK(a == Approx(kG * std::sin(theta)).epsilon(clothbench::tol::kSlideAccelerationRelative));
  }
}

TEST_CASE("the broad phase finds every pair brute force finds", "[self-contact]") {
  const std::uint64_t seed = GENERATE(11u, 12u, 13u, 14u, 15u);
  std::mt19937_64 rng(seed);
  // a crumpled 6 by 6 sheet and a loose 3 by 3 one thrown across it
  std::vector<Vector3> pts;
  std::vector<Triangle> tris;
  add_sheet(pts, tris, 6, 6, 0.1, Vector3(0, 0, 0));
  add_sheet(pts, tris, 3, 3, 0.1, Vector3(0.2, 0.2, 0.05));
  for (Vector3& p : pts)
    p += Vector3(uniform(rng, -0.06, 0.06), uniform(rng, -0.06, 0.06), uniform(rng, -0.1, 0.1));
  const Matrix3X x = to_matrix(pts);
  const int n = static_cast<int>(x.cols());
  SelfContactParams p;
  p.thickness = 0.05;
  const SelfContact contact(n, tris, p);
  const auto found = contact.proximities(x);
  const auto brute = brute_pairs(x, tris, 2 * p.thickness);
  std::set<PairKey> found_keys;
  for (const ProximityPair& q : found) {
    const PairKey key{q.kind == PairKind::kVertexTriangle ? 0 : 1, q.vertices};
    found_keys.insert(key);
    // each found pair is a brute-force pair at the same distance, within the thickness
    const auto it = brute.find(key);
    REQUIRE(it != brute.end());
    CHECK(q.distance == Approx(it->second).margin(clothbench::tol::kDistanceRoundoff));
    CHECK(q.distance < p.thickness);
  }
  CHECK(found_keys.size() == found.size());
  // and every brute-force pair within the thickness is found
  int within = 0;
  for (const auto& [key, d] : brute) {
    if (d >= p.thickness - clothbench::tol::kDistanceRoundoff) continue;
    ++within;
    CHECK(found_keys.count(key) == 1);
  }
  CHECK(within > 10);
  // closest_violation is the nearest of them
  const auto closest = contact.closest_violation(x);
  REQUIRE(closest);
  double best = p.thickness;
  for (const auto& [key, d] : brute) best = std::min(best, d);
  CHECK(closest->distance == Approx(best).margin(clothbench::tol::kDistanceRoundoff));
}

TEST_CASE("closest_violation finds a planted pair and none on a flat sheet", "[self-contact]") {
  std::vector<Vector3> pts;
  std::vector<Triangle> tris;
  add_sheet(pts, tris, 8, 8, 0.01, Vector3(0, 0, 0));
  SelfContactParams p;  // thickness 4 mm against 1 cm cells
  SECTION("flat sheet") {
    const SelfContact contact(static_cast<int>(pts.size()), tris, p);
    CHECK_FALSE(contact.closest_violation(to_matrix(pts)));
  }
  SECTION("a tilted triangle with one corner 1.5 mm above the sheet") {
    const int base = static_cast<int>(pts.size());
    pts.push_back(Vector3(0.0331, 0.0427, 0.0015));
    pts.push_back(Vector3(0.0531, 0.0427, 0.003));
    pts.push_back(Vector3(0.0331, 0.0627, 0.0035));
    tris.push_back({base, base + 1, base + 2});
    const Matrix3X x = to_matrix(pts);
    const SelfContact contact(static_cast<int>(pts.size()), tris, p);
    const auto v = contact.closest_violation(x);
    REQUIRE(v);
    CHECK(v->kind == PairKind::kVertexTriangle);
    CHECK(v->vertices[0] == base);
    CHECK(v->distance == Approx(0.0015).margin(clothbench::tol::kDistanceRoundoff));
    const auto& q = v->vertices;
    CHECK(point_triangle_distance(x.col(q[0]), x.col(q[1]), x.col(q[2]), x.col(q[3])) ==
          Approx(0.0015).margin(clothbench::tol::kDistanceRoundoff));
  }
}

TEST_CASE("self-contact refuses bad input", "[self-contact]") {
  SelfContactParams p;
  p.thickness = 0;
  CHECK_THROWS_AS(SelfContact(3, {{0, 1, 2}}, p), std::invalid_argument);
  CHECK_THROWS_AS(SelfContact(3, {{0, 1, 3}}, SelfContactParams{}), std::invalid_argument);
  CHECK_THROWS_AS(SelfContact(3, {{0, 1, 1}}, SelfContactParams{}), std::invalid_argument);
  SelfContact contact(3, {{0, 1, 2}}, SelfContactParams{});
  Matrix3X x = Matrix3X::Zero(3, 2), v = Matrix3X::Zero(3, 2);
  CHECK_THROWS_AS(contact.resolve(0.01, x, x, v, VectorX::Ones(2)), std::invalid_argument);
  Matrix3X x3 = Matrix3X::Zero(3, 3), v3 = Matrix3X::Zero(3, 3);
  CHECK_THROWS_AS(contact.resolve(0.01, x3, x3, v3, -VectorX::Ones(3)), std::invalid_argument);
  CHECK_THROWS_AS(contact.resolve(0.0, x3, x3, v3, VectorX::Ones(3)), std::invalid_argument);
}
