#include "cloth/contact/self_contact.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace cloth {
namespace {

/// Most hash cells one box enters; a larger box is checked against every element instead.
constexpr std::int64_t kMaxCells = 64;
/// Cell coordinates are clamped so that huge positions stay integers (monotone: boxes that
/// overlap still share a cell).
constexpr double kCellClamp = 1099511627776.0;
/// A cubic value this small relative to the sum of its coefficients' sizes counts as a root
/// candidate (a touch without sign change); every candidate is confirmed by a distance.
constexpr double kFlatCubic = 1e-12;
/// Below this fraction of the collision distance the closest-point direction is noise, and a
/// collision's normal comes from the elements' plane instead.
constexpr double kNormalFromPlane = 1e-3;
/// The candidates hold while each vertex stays within its radius of where it was at the build:
/// kRadiusFloor times the thickness plus kSlackSteps times its move over the path they were
/// built for, so for several steps of a steady motion.
constexpr double kSlackSteps = 8.0;
constexpr double kRadiusFloor = 0.5;
/// A candidate is left out when its distance exceeds this times the most its elements can
/// approach inside their vertices' balls plus the gap; the 1 % covers round-off many times.
constexpr double kPruneMargin = 1.01;
/// activate() sorts the candidates near enough when they are at most 1 / kFewActive of all.
constexpr std::size_t kFewActive = 8;

struct Aabb {
  Vector3 lo, hi;
};

struct CellRange {
  std::int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool too_many = false;
};

std::int64_t cell_of(double q) {
  if (!(q == q)) return 0;
  return static_cast<std::int64_t>(std::clamp(std::floor(q), -kCellClamp, kCellClamp));
}

CellRange cell_range(const Aabb& b, double cell) {
  CellRange c;
  std::int64_t count = 1;
  for (int k = 0; k < 3; ++k) {
    c.lo[k] = cell_of(b.lo[k] / cell);
    c.hi[k] = cell_of(b.hi[k] / cell);
    count *= std::min<std::int64_t>(c.hi[k] - c.lo[k] + 1, kMaxCells + 1);
    count = std::min<std::int64_t>(count, kMaxCells + 1);
  }
  c.too_many = count > kMaxCells;
  return c;
}

std::size_t bucket_of(std::int64_t i, std::int64_t j, std::int64_t k, std::size_t mask) {
  std::uint64_t h = std::uint64_t(i) * 0x9E3779B97F4A7C15ull;
  h ^= std::uint64_t(j) * 0xC2B2AE3D27D4EB4Full;
  h ^= std::uint64_t(k) * 0x165667B19E3779F9ull;
  h ^= h >> 31;
  return static_cast<std::size_t>(h) & mask;
}

template <class F>
void for_each_cell(const CellRange& c, F&& f) {
  for (std::int64_t i = c.lo[0]; i <= c.hi[0]; ++i)
    for (std::int64_t j = c.lo[1]; j <= c.hi[1]; ++j)
      for (std::int64_t k = c.lo[2]; k <= c.hi[2]; ++k) f(i, j, k);
}

bool overlap(const Aabb& a, const Aabb& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

/// True when the box of the pair's first element (its vertex or first edge) swept from a to
/// b (3 by #P, m) and inflated by pad (m) overlaps the box of its second element: the same
/// test, to the bit, as the broad phase's on unpadded swept boxes.
bool near_pair(PairKind kind, const std::array<int, 4>& q, const Matrix3X& a, const Matrix3X& b,
               double pad) {
  const int split = kind == PairKind::kVertexTriangle ? 1 : 2;
  Aabb one{a.col(q[0]).cwiseMin(b.col(q[0])), a.col(q[0]).cwiseMax(b.col(q[0]))};
  Aabb two{a.col(q[split]).cwiseMin(b.col(q[split])), a.col(q[split]).cwiseMax(b.col(q[split]))};
  for (int i = 1; i < 4; ++i) {
    Aabb& into = i < split ? one : two;
    if (i == split) continue;
    into.lo = into.lo.cwiseMin(a.col(q[i]).cwiseMin(b.col(q[i])));
    into.hi = into.hi.cwiseMax(a.col(q[i]).cwiseMax(b.col(q[i])));
  }
  one.lo.array() -= pad;
  one.hi.array() += pad;
  return overlap(one, two);
}

/// Boxes hashed into uniform cells, rebuilt per query set; buffers kept between builds.
struct BoxHash {
  double cell = 1;
  std::size_t mask = 0;
  std::vector<int> start, item, big, fill;
  std::vector<CellRange> ranges;

  void build(const std::vector<Aabb>& boxes, double cell_size) {
    cell = cell_size;
    std::size_t table = 1;
    while (table < 2 * boxes.size()) table *= 2;
    mask = table - 1;
    start.assign(table + 1, 0);
    ranges.resize(boxes.size());
    big.clear();
    // count each bucket's entries, then fill them in element order
    for (std::size_t t = 0; t < boxes.size(); ++t) {
      ranges[t] = cell_range(boxes[t], cell);
      if (ranges[t].too_many) {
        big.push_back(static_cast<int>(t));
        continue;
      }
      for_each_cell(ranges[t], [&](std::int64_t i, std::int64_t j, std::int64_t k) {
        ++start[bucket_of(i, j, k, mask) + 1];
      });
    }
    for (std::size_t b = 0; b < table; ++b) start[b + 1] += start[b];
    item.resize(static_cast<std::size_t>(start[table]));
    fill.assign(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < boxes.size(); ++t) {
      if (ranges[t].too_many) continue;
      for_each_cell(ranges[t], [&](std::int64_t i, std::int64_t j, std::int64_t k) {
        item[static_cast<std::size_t>(fill[bucket_of(i, j, k, mask)]++)] = static_cast<int>(t);
      });
    }
  }

  /// Calls f(t) once for every element whose cells the box q shares (or that is too big).
  template <class F>
  void visit(const Aabb& q, std::vector<int>& stamp, int query, F&& f) const {
    const auto once = [&](int t) {
      if (stamp[t] == query) return;
      stamp[t] = query;
      f(t);
    };
    const CellRange c = cell_range(q, cell);
    if (c.too_many) {
      for (int t = 0; t < static_cast<int>(ranges.size()); ++t) once(t);
      return;
    }
    for_each_cell(c, [&](std::int64_t i, std::int64_t j, std::int64_t k) {
      const std::size_t b = bucket_of(i, j, k, mask);
      for (int n = start[b]; n < start[b + 1]; ++n) once(item[n]);
    });
    for (int t : big) once(t);
  }
};

/// The closest points of a pair as weights on its four points (summing to zero: +1 side
/// minus -1 side), their difference and its length (m).
struct Closest {
  std::array<double, 4> w = {0, 0, 0, 0};
  Vector3 diff = Vector3::Zero();
  double dist = 0;
};

double clamp01(double t) {
  return std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
}

/// Parameter of the point of segment [a, b] closest to p.
double segment_param(const Vector3& p, const Vector3& a, const Vector3& b) {
  const double len2 = (b - a).squaredNorm();
  return len2 > 0 ? clamp01((p - a).dot(b - a) / len2) : 0.0;
}

/// Barycentric weights of the point of triangle (a, b, c) closest to p, by the Voronoi region
/// of p; a collapsed triangle falls back to the best of its three sides.
std::array<double, 3> triangle_weights(const Vector3& p, const Vector3& a, const Vector3& b,
                                       const Vector3& c) {
  const Vector3 ab = b - a, ac = c - a, ap = p - a, bp = p - b, cp = p - c;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap), d3 = ab.dot(bp), d4 = ac.dot(bp);
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  // vertex and side regions
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) {
    const double t = d1 / (d1 - d3);
    return {1 - t, t, 0};
  }
  if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) {
    const double t = d2 / (d2 - d6);
    return {1 - t, 0, t};
  }
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 && (d4 - d3) + (d5 - d6) > 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - t, t};
  }
  const double denom = va + vb + vc;
  if (denom > 0 && std::isfinite(denom)) return {va / denom, vb / denom, vc / denom};
  // a collapsed triangle: its best side
  const double s = segment_param(p, a, b), t = segment_param(p, b, c), u = segment_param(p, c, a);
  const double ds = (p - (a + s * (b - a))).squaredNorm(),
               dt = (p - (b + t * (c - b))).squaredNorm();
  const double du = (p - (c + u * (a - c))).squaredNorm();
  if (ds <= dt && ds <= du) return {1 - s, s, 0};
  if (dt <= du) return {0, 1 - t, t};
  return {u, 0, 1 - u};
}

/// Parameters (s, t) of the closest points of segments [p0, p1] and [q0, q1]: the common
/// perpendicular when its feet are inside, and the four endpoint projections, whichever is
/// closest (so near-parallel segments get the right distance).
std::array<double, 2> segment_params(const Vector3& p0, const Vector3& p1, const Vector3& q0,
                                     const Vector3& q1) {
  const Vector3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  std::array<std::array<double, 2>, 5> cand = {{{0, segment_param(p0, q0, q1)},
                                                {1, segment_param(p1, q0, q1)},
                                                {segment_param(q0, p0, p1), 0},
                                                {segment_param(q1, p0, p1), 1},
                                                {-1, -1}}};
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), b = d1.dot(d2);
  const double denom = a * e - b * b;
  if (denom > 0 && std::isfinite(denom)) {
    const double s = (b * d2.dot(r) - d1.dot(r) * e) / denom;
    const double t = (a * d2.dot(r) - b * d1.dot(r)) / denom;
    if (s > 0 && s < 1 && t > 0 && t < 1) cand[4] = {s, t};
  }
  std::array<double, 2> best = cand[0];
  double best_d = std::numeric_limits<double>::infinity();
  for (const auto& c : cand) {
    if (c[0] < 0) continue;
    const double d = ((p0 + c[0] * d1) - (q0 + c[1] * d2)).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

/// The closest points of a pair at positions p (vertex, triangle or edge, edge).
Closest closest(PairKind kind, const Vector3 (&p)[4]) {
  Closest c;
  if (kind == PairKind::kVertexTriangle) {
    const auto b = triangle_weights(p[0], p[1], p[2], p[3]);
    c.w = {1, -b[0], -b[1], -b[2]};
  } else {
    const auto st = segment_params(p[0], p[1], p[2], p[3]);
    c.w = {1 - st[0], st[0], -(1 - st[1]), -st[1]};
  }
  for (int i = 0; i < 4; ++i) c.diff += c.w[i] * p[i];
  c.dist = c.diff.norm();
  return c;
}

/// The pair's plane normal (unnormalised): the triangle's, or the two edges' cross product.
Vector3 plane_normal(PairKind kind, const Vector3 (&p)[4]) {
  if (kind == PairKind::kVertexTriangle) return (p[2] - p[1]).cross(p[3] - p[1]);
  return (p[1] - p[0]).cross(p[3] - p[2]);
}

/// Insertion sort of a handful of values.
void sort_small(double* begin, double* end) {
  for (double* i = begin; i < end; ++i)
    for (double* j = i; j > begin && *(j - 1) > *j; --j) std::swap(*(j - 1), *j);
}

double cubic(const std::array<double, 4>& k, double t) {
  return ((k[3] * t + k[2]) * t + k[1]) * t + k[0];
}

/// The cubic's roots in [0, 1], ascending, at most 7: sign changes on its monotone pieces,
/// bisected to the last bit, and piece ends where it nearly vanishes (touches). An
/// identically zero cubic (motion inside one plane) gives 0, 0.5 and 1 to check.
int unit_roots(const std::array<double, 4>& k, double (&out)[7]) {
  const double scale = std::abs(k[0]) + std::abs(k[1]) + std::abs(k[2]) + std::abs(k[3]);
  if (!(scale > 0) || !std::isfinite(scale)) {
    out[0] = 0, out[1] = 0.5, out[2] = 1;
    return 3;
  }
  // the derivative's roots split [0, 1] into monotone pieces
  double ends[4] = {0, 1, 1, 1};
  int m = 1;
  const double qa = 3 * k[3], qb = 2 * k[2], qc = k[1];
  const auto add_end = [&](double t) {
    if (t > 0 && t < 1) ends[m++] = t;
  };
  if (qa == 0) {
    if (qb != 0) add_end(-qc / qb);
  } else {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc >= 0) {
      const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      add_end(q / qa);
      if (q != 0) add_end(qc / q);
    }
  }
  sort_small(ends + 1, ends + m);
  ends[m++] = 1;
  int n = 0;
  for (int i = 0; i < m; ++i)
    if (std::abs(cubic(k, ends[i])) <= kFlatCubic * scale) out[n++] = ends[i];
  // sign changes, bisected
  for (int i = 0; i + 1 < m; ++i) {
    double lo = ends[i], hi = ends[i + 1];
    const double flo = cubic(k, lo), fhi = cubic(k, hi);
    if (!((flo < 0 && fhi > 0) || (flo > 0 && fhi < 0))) continue;
    for (int it = 0; it < 64 && lo < hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      const double fm = cubic(k, mid);
      if ((fm < 0) == (flo < 0) && fm != 0)
        lo = mid;
      else
        hi = mid;
    }
    out[n++] = hi;
  }
  sort_small(out, out + n);
  int unique = 0;
  for (int i = 0; i < n; ++i)
    if (unique == 0 || out[i] != out[unique - 1]) out[unique++] = out[i];
  return unique;
}

/// The coplanarity cubic of four points moving from x by u over t in [0, 1].
std::array<double, 4> coplanarity(PairKind kind, const Vector3 (&x)[4], const Vector3 (&u)[4]) {
  // origin o and the three others, relative to it
  const int o = kind == PairKind::kVertexTriangle ? 1 : 0;
  const int e[3] = {kind == PairKind::kVertexTriangle ? 2 : 1,
                    kind == PairKind::kVertexTriangle ? 3 : 2,
                    kind == PairKind::kVertexTriangle ? 0 : 3};
  const Vector3 a = x[e[0]] - x[o], b = x[e[1]] - x[o], c = x[e[2]] - x[o];
  const Vector3 da = u[e[0]] - u[o], db = u[e[1]] - u[o], dc = u[e[2]] - u[o];
  const Vector3 ab = a.cross(b), mixed = a.cross(db) + da.cross(b), dadb = da.cross(db);
  return {ab.dot(c), ab.dot(dc) + mixed.dot(c), mixed.dot(dc) + dadb.dot(c), dadb.dot(dc)};
}

/// The earliest time in [0, 1] at which the pair moving from x by u collides: comes closer
/// than eta (m) when coplanar, or ends closer than eta and than it started. -1 when none.
double collision_time(PairKind kind, const Vector3 (&x)[4], const Vector3 (&u)[4], double eta) {
  double roots[7];
  const int n = unit_roots(coplanarity(kind, x, u), roots);
  Vector3 p[4];
  for (int r = 0; r < n; ++r) {
    for (int i = 0; i < 4; ++i) p[i] = x[i] + roots[r] * u[i];
    if (closest(kind, p).dist < eta) return roots[r];
  }
  for (int i = 0; i < 4; ++i) p[i] = x[i] + u[i];
  const double end = closest(kind, p).dist;
  return end < eta && end < closest(kind, x).dist ? 1.0 : -1.0;
}

/// The zone root of v (the smallest index of its zone), halving the paths on the way.
int find_root(std::vector<int>& parent, int v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

}  // namespace

/// Buffers of the broad phase and its candidates, kept between calls.
struct SelfContact::Scratch {
  std::vector<Aabb> vert_box;           // #P boxes around the anchors' balls (m)
  Matrix3X anchor;                      // 3 by #P positions the candidates were built at (m)
  std::vector<double> radius;           // #P the candidates hold while every vertex stays
                                        // this close to its anchor (m)
  std::vector<double> disp;             // #P distance of the current path from the anchor (m)
  std::vector<Aabb> tri_box, edge_box;  // element boxes, unions of their vertices' (m)
  std::vector<double> sizes;            // triangle box extents, for the cell size
  BoxHash tri_hash, edge_hash;
  std::vector<int> tri_stamp, edge_stamp;
  std::vector<ProximityPair> pairs;  // candidates of the last collect_pairs, sorted
  std::vector<char> far;             // per candidate: more than two rings apart
  std::vector<int> by_distance;      // candidates by their distance at the anchors
  std::vector<int> active;           // candidates that may come close on the current paths
  double max_disp = 0;               // m, the largest disp
  bool cached = false;               // pairs hold for every path inside the balls
  Matrix3X end;                      // 3 by #P end positions of the current vbar' (m)

  /// The candidates into active, in order: those not apart by their distance alone with every
  /// vertex within max_disp of its anchor when they are few (sorting them is then cheap),
  /// else all of them.
  void activate(double gap) {
    const double reach = kPruneMargin * (2 * max_disp + gap);
    const auto last = std::partition_point(by_distance.begin(), by_distance.end(),
                                           [&](int i) { return !(pairs[i].distance > reach); });
    if (static_cast<std::size_t>(last - by_distance.begin()) * kFewActive > pairs.size()) {
      active.resize(pairs.size());
      std::iota(active.begin(), active.end(), 0);
      return;
    }
    active.assign(by_distance.begin(), last);
    std::sort(active.begin(), active.end());
  }
  /// True when candidate q (distance at the anchors) stays farther apart than gap (m) while
  /// each vertex is within move (#P, m) of its anchor: each point of an element is then within
  /// its vertices' largest move of where it was at the anchors.
  bool apart(const ProximityPair& q, const std::vector<double>& move, double gap) const;
};

/// One resolve call's inputs and running results.
struct SelfContact::Pass {
  double h;
  const Matrix3X& x0;
  const VectorX& inv_mass;
  Scratch& s;
  Matrix3X& vbar;
  SelfContactStats stats;

  void load(const ProximityPair& q, Vector3 (&x)[4], Vector3 (&u)[4]) const {
    for (int i = 0; i < 4; ++i) {
      x[i] = x0.col(q.vertices[i]);
      u[i] = h * vbar.col(q.vertices[i]);
    }
  }
  /// Changes vbar' so that the pair's relative velocity sum w_i vbar'_i changes by dv (m/s),
  /// with impulses w_i J on the points (they sum to zero); false when all are heavy.
  bool apply(const ProximityPair& q, const std::array<double, 4>& w, const Vector3& dv) {
    double weight = 0;
    for (int i = 0; i < 4; ++i) weight += w[i] * w[i] * inv_mass[q.vertices[i]];
    if (!(weight > 0)) return false;
    const Vector3 impulse = dv / weight;
    for (int i = 0; i < 4; ++i)
      vbar.col(q.vertices[i]) += (w[i] * inv_mass[q.vertices[i]]) * impulse;
    return true;
  }
  Vector3 relative_velocity(const ProximityPair& q, const std::array<double, 4>& w) const {
    Vector3 r = Vector3::Zero();
    for (int i = 0; i < 4; ++i) r += w[i] * vbar.col(q.vertices[i]);
    return r;
  }
};

SelfContact::ScratchHolder::ScratchHolder() : ptr(std::make_unique<Scratch>()) {}
SelfContact::ScratchHolder::~ScratchHolder() = default;
SelfContact::ScratchHolder::ScratchHolder(const ScratchHolder&)
    : ptr(std::make_unique<Scratch>()) {}
SelfContact::ScratchHolder& SelfContact::ScratchHolder::operator=(const ScratchHolder&) {
  return *this;
}

void SelfContact::forget_candidates() {
  m_scratch.ptr->cached = false;
}

SelfContact::SelfContact(int particle_count, std::vector<Triangle> triangles, SelfContactParams p)
    : m_count(particle_count), m_triangles(std::move(triangles)), m_params(p) {
  if (particle_count < 0) throw std::invalid_argument("self-contact: negative particle count");
  if (!(p.thickness > 0) || !std::isfinite(p.thickness))
    throw std::invalid_argument("self-contact: thickness must be positive and finite, got " +
                                std::to_string(p.thickness));
  if (!(p.friction >= 0) || !std::isfinite(p.friction) || !(p.repulsion_stiffness >= 0) ||
      !(p.aim_gap > p.min_gap) || !(p.min_gap > 0) || !(p.rest_gap > p.aim_gap) ||
      !(p.rest_gap <= 1) || p.ccd_iterations < 0 || p.zone_iterations < 1)
    throw std::invalid_argument(
        "self-contact: friction and repulsion_stiffness must be >= 0, "
        "0 < min_gap < aim_gap < rest_gap <= 1, ccd_iterations >= 0 "
        "and zone_iterations >= 1");
  // the unique edges
  for (std::size_t t = 0; t < m_triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = m_triangles[t][k], b = m_triangles[t][(k + 1) % 3];
      if (a < 0 || a >= particle_count || b < 0 || b >= particle_count || a == b)
        throw std::invalid_argument("self-contact: triangle " + std::to_string(t) +
                                    " has a vertex out of range or repeated");
      m_edges.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(m_edges.begin(), m_edges.end());
  m_edges.erase(std::unique(m_edges.begin(), m_edges.end()), m_edges.end());
  // neighbour lists (sorted, since the edges are)
  m_adj_start.assign(static_cast<std::size_t>(particle_count) + 1, 0);
  for (const auto& e : m_edges) ++m_adj_start[e[0] + 1], ++m_adj_start[e[1] + 1];
  for (int v = 0; v < particle_count; ++v) m_adj_start[v + 1] += m_adj_start[v];
  m_adj.assign(static_cast<std::size_t>(m_adj_start[particle_count]), 0);
  std::vector<int> fill(m_adj_start.begin(), m_adj_start.end() - 1);
  for (const auto& e : m_edges) m_adj[fill[e[0]]++] = e[1], m_adj[fill[e[1]]++] = e[0];
  for (int v = 0; v < particle_count; ++v)
    std::sort(m_adj.begin() + m_adj_start[v], m_adj.begin() + m_adj_start[v + 1]);
}

bool SelfContact::within_two_rings(int v, int w) const {
  if (v == w) return true;
  const auto vb = m_adj.begin() + m_adj_start[v], ve = m_adj.begin() + m_adj_start[v + 1];
  const auto wb = m_adj.begin() + m_adj_start[w], we = m_adj.begin() + m_adj_start[w + 1];
  if (std::binary_search(vb, ve, w)) return true;
  // a common neighbour: merge the two sorted lists
  for (auto i = vb, j = wb; i != ve && j != we;) {
    if (*i == *j) return true;
    if (*i < *j)
      ++i;
    else
      ++j;
  }
  return false;
}

bool SelfContact::excluded(PairKind kind, const std::array<int, 4>& q, bool rings) const {
  if (!rings) {
    // only pairs sharing a vertex
    const int split = kind == PairKind::kVertexTriangle ? 1 : 2;
    for (int i = 0; i < split; ++i)
      for (int j = split; j < 4; ++j)
        if (q[i] == q[j]) return true;
    return false;
  }
  if (kind == PairKind::kVertexTriangle)
    return within_two_rings(q[0], q[1]) || within_two_rings(q[0], q[2]) ||
           within_two_rings(q[0], q[3]);
  for (int i = 0; i < 2; ++i)
    for (int j = 2; j < 4; ++j)
      if (within_two_rings(q[i], q[j])) return true;
  return false;
}

void SelfContact::collect_pairs(double pad, bool rings, Scratch& s) const {
  const auto merge = [](Aabb& into, const Aabb& other) {
    into.lo = into.lo.cwiseMin(other.lo);
    into.hi = into.hi.cwiseMax(other.hi);
  };
  // the triangles' and edges' boxes from their vertices'
  const std::vector<Aabb>& vb = s.vert_box;
  s.tri_box.resize(m_triangles.size());
  s.sizes.resize(m_triangles.size());
  for (std::size_t t = 0; t < m_triangles.size(); ++t) {
    Aabb box = vb[m_triangles[t][0]];
    merge(box, vb[m_triangles[t][1]]);
    merge(box, vb[m_triangles[t][2]]);
    s.tri_box[t] = box;
    s.sizes[t] = (box.hi - box.lo).maxCoeff();
  }
  s.edge_box.resize(m_edges.size());
  for (std::size_t e = 0; e < m_edges.size(); ++e) {
    Aabb box = vb[m_edges[e][0]];
    merge(box, vb[m_edges[e][1]]);
    s.edge_box[e] = box;
  }
  // cells: the median triangle box, at least twice the padding
  double cell = 2 * pad;
  if (!s.sizes.empty()) {
    const auto mid = s.sizes.begin() + static_cast<std::ptrdiff_t>(s.sizes.size() / 2);
    std::nth_element(s.sizes.begin(), mid, s.sizes.end());
    cell = std::max(cell, *mid);
  }
  if (!(cell > 0) || !std::isfinite(cell)) cell = 1;
  s.tri_hash.build(s.tri_box, cell);
  s.edge_hash.build(s.edge_box, cell);
  s.tri_stamp.assign(m_triangles.size(), -1);
  s.edge_stamp.assign(m_edges.size(), -1);
  s.pairs.clear();
  const auto inflate = [&](Aabb box) {
    box.lo.array() -= pad;
    box.hi.array() += pad;
    return box;
  };
  // each element's pairs sorted by vertices, so that the order does not depend on the cells
  const auto sort_from = [&](std::size_t first) {
    std::sort(
        s.pairs.begin() + static_cast<std::ptrdiff_t>(first), s.pairs.end(),
        [](const ProximityPair& l, const ProximityPair& r) { return l.vertices < r.vertices; });
  };
  // vertices against triangles, then edges against edges of higher index
  for (int v = 0; v < m_count; ++v) {
    const Aabb box = inflate(vb[v]);
    const std::size_t first = s.pairs.size();
    s.tri_hash.visit(box, s.tri_stamp, v, [&](int t) {
      const Triangle& tri = m_triangles[t];
      const std::array<int, 4> q = {v, tri[0], tri[1], tri[2]};
      if (overlap(box, s.tri_box[t]) && !excluded(PairKind::kVertexTriangle, q, rings))
        s.pairs.push_back({PairKind::kVertexTriangle, q, 0.0});
    });
    sort_from(first);
  }
  for (int e = 0; e < static_cast<int>(m_edges.size()); ++e) {
    const Aabb box = inflate(s.edge_box[e]);
    const std::size_t first = s.pairs.size();
    s.edge_hash.visit(box, s.edge_stamp, e, [&](int f) {
      const std::array<int, 4> q = {m_edges[e][0], m_edges[e][1], m_edges[f][0], m_edges[f][1]};
      if (f > e && overlap(box, s.edge_box[f]) && !excluded(PairKind::kEdgeEdge, q, rings))
        s.pairs.push_back({PairKind::kEdgeEdge, q, 0.0});
    });
    sort_from(first);
  }
}

std::int64_t SelfContact::update_candidates(const Matrix3X& a, const Matrix3X& b,
                                            Scratch& s) const {
  // still good when every vertex's path from a to b stays within the radius of its anchor
  bool inside = s.cached;
  s.disp.resize(static_cast<std::size_t>(m_count));
  s.max_disp = 0;
  for (int v = 0; v < m_count && inside; ++v) {
    s.disp[v] = std::max((a.col(v) - s.anchor.col(v)).norm(), (b.col(v) - s.anchor.col(v)).norm());
    inside = s.disp[v] <= s.radius[v];
    s.max_disp = std::max(s.max_disp, s.disp[v]);
  }
  if (inside) return 0;
  s.max_disp = 0;
  // anchors at a; radii from each vertex's move a -> b
  s.anchor = a;
  s.radius.resize(static_cast<std::size_t>(m_count));
  s.vert_box.resize(static_cast<std::size_t>(m_count));
  for (int v = 0; v < m_count; ++v) {
    s.disp[v] = (b.col(v) - a.col(v)).norm();
    s.max_disp = std::max(s.max_disp, s.disp[v]);
    s.radius[v] = kRadiusFloor * m_params.thickness + kSlackSteps * s.disp[v];
    if (!std::isfinite(s.radius[v])) s.radius[v] = kRadiusFloor * m_params.thickness;
    s.vert_box[v] = Aabb{a.col(v).array() - s.radius[v], a.col(v).array() + s.radius[v]};
  }
  collect_pairs(m_params.thickness, !m_params.near_collisions, s);
  s.cached = true;
  // keep the pairs closer at the anchors than the thickness plus their elements' largest
  // radii (the most two points of them can approach while every vertex stays within its
  // radius), with their distance there
  std::size_t kept = 0;
  Vector3 x[4];
  for (std::size_t i = 0; i < s.pairs.size(); ++i) {
    ProximityPair q = s.pairs[i];
    for (int k = 0; k < 4; ++k) x[k] = a.col(q.vertices[k]);
    q.distance = closest(q.kind, x).dist;
    if (s.apart(q, s.radius, m_params.thickness)) continue;
    s.pairs[kept++] = q;
  }
  const auto tests = static_cast<std::int64_t>(s.pairs.size());
  s.pairs.resize(kept);
  // which of them the proximity stage sees
  s.far.resize(kept);
  for (std::size_t i = 0; i < kept; ++i)
    s.far[i] = !m_params.near_collisions || !excluded(s.pairs[i].kind, s.pairs[i].vertices, true);
  // and by their distance, for activate(); NaN distances (never apart) first
  s.by_distance.resize(kept);
  for (std::size_t i = 0; i < kept; ++i) s.by_distance[i] = static_cast<int>(i);
  std::sort(s.by_distance.begin(), s.by_distance.end(), [&](int l, int r) {
    const double dl = s.pairs[l].distance, dr = s.pairs[r].distance;
    return (std::isnan(dl) && !std::isnan(dr)) || dl < dr;
  });
  return tests;
}

bool SelfContact::Scratch::apart(const ProximityPair& q, const std::vector<double>& move,
                                 double gap) const {
  const int split = q.kind == PairKind::kVertexTriangle ? 1 : 2;
  double reach[2] = {0, 0};
  for (int k = 0; k < 4; ++k) reach[k >= split] = std::max(reach[k >= split], move[q.vertices[k]]);
  return q.distance > kPruneMargin * (reach[0] + reach[1] + gap);
}

std::vector<ProximityPair> SelfContact::proximities(const Matrix3X& x) const {
  if (x.cols() != m_count)
    throw std::invalid_argument("self-contact: " + std::to_string(x.cols()) + " positions for " +
                                std::to_string(m_count) + " particles");
  Scratch s;
  s.vert_box.resize(static_cast<std::size_t>(m_count));
  for (int v = 0; v < m_count; ++v) s.vert_box[v] = Aabb{x.col(v), x.col(v)};
  collect_pairs(m_params.thickness, true, s);
  std::vector<ProximityPair> out;
  Vector3 p[4];
  for (ProximityPair q : s.pairs) {
    for (int i = 0; i < 4; ++i) p[i] = x.col(q.vertices[i]);
    q.distance = closest(q.kind, p).dist;
    if (q.distance < m_params.thickness) out.push_back(q);
  }
  // vertex-triangle pairs first, each kind in element order
  std::stable_sort(out.begin(), out.end(), [](const ProximityPair& l, const ProximityPair& r) {
    return std::make_pair(l.kind, l.vertices) < std::make_pair(r.kind, r.vertices);
  });
  return out;
}

std::optional<ProximityPair> SelfContact::closest_violation(const Matrix3X& x) const {
  std::optional<ProximityPair> best;
  for (const ProximityPair& q : proximities(x))
    if (!best || q.distance < best->distance) best = q;
  return best;
}

void SelfContact::proximity_pass(Pass& p) {
  const double thick = m_params.thickness;
  p.s.end = p.x0 + p.h * p.vbar;
  p.stats.tests += update_candidates(p.x0, p.s.end, p.s);
  p.s.activate(thick);
  Vector3 x[4];
  for (int k : p.s.active) {
    const ProximityPair& q = p.s.pairs[k];
    if (!p.s.far[k] || p.s.apart(q, p.s.disp, thick) ||
        !near_pair(q.kind, q.vertices, p.x0, p.x0, thick))
      continue;
    for (int i = 0; i < 4; ++i) x[i] = p.x0.col(q.vertices[i]);
    ++p.stats.tests;
    const Closest c = closest(q.kind, x);
    if (!(c.dist < thick)) continue;
    ++p.stats.proximities;
    // the normal from the closest points (the plane's when they coincide)
    Vector3 n = c.dist > 0 ? Vector3(c.diff / c.dist) : plane_normal(q.kind, x).normalized();
    if (!n.allFinite() || n.squaredNorm() == 0) continue;
    const Vector3 rel = p.relative_velocity(q, c.w);
    const double vn = rel.dot(n);
    // inelastic: stop the approach; repulsion: up to 0.1 gap / h, at most the spring impulse,
    // towards the rest gap just inside the band (a resting pair stays in contact)
    double dvn = std::max(0.0, -vn);
    const double gap = std::max(0.0, m_params.rest_gap * thick - c.dist);
    const double target = 0.1 * gap / p.h;
    double weight = 0;
    for (int i = 0; i < 4; ++i) weight += c.w[i] * c.w[i] * p.inv_mass[q.vertices[i]];
    if (vn + dvn < target)
      dvn += std::min(p.h * m_params.repulsion_stiffness * gap * weight, target - (vn + dvn));
    // coulomb friction: the tangential speed falls by at most mu times the normal change
    const Vector3 vt = rel - vn * n;
    const double vt_norm = vt.norm();
    Vector3 dv = dvn * n;
    if (vt_norm > 0) dv -= std::min(m_params.friction * dvn, vt_norm) / vt_norm * vt;
    p.apply(q, c.w, dv);
  }
}

int SelfContact::collision_round(Pass& p, bool impulses, bool skip_rigid) {
  const double eta = m_params.min_gap * m_params.thickness;
  const double aim = m_params.aim_gap * m_params.thickness;
  p.s.end = p.x0 + p.h * p.vbar;
  p.stats.tests += update_candidates(p.x0, p.s.end, p.s);
  p.s.activate(eta);
  int found = 0;
  Vector3 x[4], u[4], xt[4];
  for (int k : p.s.active) {
    const ProximityPair& q = p.s.pairs[k];
    // the candidates whose paths at the round's start come within eta
    if (p.s.apart(q, p.s.disp, eta) || !near_pair(q.kind, q.vertices, p.x0, p.s.end, eta)) continue;
    // a pair of infinitely heavy vertices only (held, handled or on a collider) is moved by
    // what holds them, which no impulse or zone can change
    if (p.inv_mass[q.vertices[0]] == 0 && p.inv_mass[q.vertices[1]] == 0 &&
        p.inv_mass[q.vertices[2]] == 0 && p.inv_mass[q.vertices[3]] == 0)
      continue;
    // pairs inside one rigidly moving zone cannot come closer
    if (skip_rigid) {
      const int root = find_root(m_parent, q.vertices[0]);
      if (m_rigid[root] && find_root(m_parent, q.vertices[1]) == root &&
          find_root(m_parent, q.vertices[2]) == root && find_root(m_parent, q.vertices[3]) == root)
        continue;
    }
    p.load(q, x, u);
    ++p.stats.tests;
    const double tau = collision_time(q.kind, x, u, eta);
    if (tau < 0) continue;
    ++found;
    if (!impulses) {
      // merge the pair's vertices into one zone
      for (int i = 1; i < 4; ++i) {
        const int a = find_root(m_parent, q.vertices[0]), b = find_root(m_parent, q.vertices[i]);
        if (a != b) m_parent[std::max(a, b)] = std::min(a, b);
      }
      continue;
    }
    // the normal at the collision time, oriented along the start separation
    for (int i = 0; i < 4; ++i) xt[i] = x[i] + tau * u[i];
    const Closest c = closest(q.kind, xt);
    Vector3 n = c.dist > kNormalFromPlane * eta ? Vector3(c.diff / c.dist)
                                                : plane_normal(q.kind, xt).normalized();
    if (!n.allFinite() || n.squaredNorm() == 0) n = c.diff.normalized();
    if (!n.allFinite() || n.squaredNorm() == 0) continue;
    Vector3 start = Vector3::Zero();
    for (int i = 0; i < 4; ++i) start += c.w[i] * x[i];
    double s0 = start.dot(n);
    if (s0 < 0) n = -n, s0 = -s0;
    // inelastic impulse aiming the end separation along n at the aim gap
    const double vn = p.relative_velocity(q, c.w).dot(n), target = (aim - s0) / p.h;
    if (vn < target) p.apply(q, c.w, (target - vn) * n);
  }
  p.stats.ccd_collisions += found;
  return found;
}

void SelfContact::rigidify(Pass& p, int root, const std::vector<int>& members) {
  // a zone with heavy vertices: the free ones move with the heavy ones' mean velocity
  Vector3 heavy = Vector3::Zero();
  int heavy_count = 0;
  bool same = true;
  int first = -1;
  for (int v : members)
    if (!(p.inv_mass[v] > 0)) {
      if (first < 0) first = v;
      if (p.vbar.col(v) != p.vbar.col(first)) same = false;
      heavy += p.vbar.col(v);
      ++heavy_count;
    }
  if (heavy_count > 0) {
    heavy /= heavy_count;
    for (int v : members)
      if (p.inv_mass[v] > 0) p.vbar.col(v) = heavy;
    m_rigid[root] = same;
    return;
  }
  // centre of mass, its velocity, angular momentum and inertia about it (at x_start)
  double mass = 0;
  Vector3 centre = Vector3::Zero(), velocity = Vector3::Zero();
  for (int v : members) {
    const double m = 1.0 / p.inv_mass[v];
    mass += m;
    centre += m * p.x0.col(v);
    velocity += m * p.vbar.col(v);
  }
  centre /= mass;
  velocity /= mass;
  Vector3 momentum = Vector3::Zero();
  Matrix3 inertia = Matrix3::Zero();
  for (int v : members) {
    const double m = 1.0 / p.inv_mass[v];
    const Vector3 r = p.x0.col(v) - centre;
    momentum += m * r.cross(Vector3(p.vbar.col(v)) - velocity);
    inertia += m * (r.squaredNorm() * Matrix3::Identity() - r * r.transpose());
  }
  // the angular velocity, pseudo-inverting a singular inertia (a collinear zone)
  const Eigen::SelfAdjointEigenSolver<Matrix3> eig(inertia);
  const double largest = eig.eigenvalues().cwiseAbs().maxCoeff();
  Vector3 omega = Vector3::Zero();
  for (int k = 0; k < 3; ++k)
    if (eig.eigenvalues()[k] > 1e-12 * largest)
      omega += eig.eigenvectors().col(k) *
               (eig.eigenvectors().col(k).dot(momentum) / eig.eigenvalues()[k]);
  for (int v : members) p.vbar.col(v) = velocity + omega.cross(Vector3(p.x0.col(v) - centre));
  m_rigid[root] = 1;
}

bool SelfContact::zone_pass(Pass& p) {
  m_parent.resize(static_cast<std::size_t>(m_count));
  for (int v = 0; v < m_count; ++v) m_parent[v] = v;
  m_rigid.assign(static_cast<std::size_t>(m_count), 1);
  std::vector<int>& members = m_members;
  for (int round = 0; round < m_params.zone_iterations; ++round) {
    const bool clear = collision_round(p, false, true) == 0;
    // the zones (two or more vertices), grouped by root in vertex order
    m_zone_start.assign(static_cast<std::size_t>(m_count) + 1, 0);
    for (int v = 0; v < m_count; ++v) m_parent[v] = find_root(m_parent, v);
    for (int v = 0; v < m_count; ++v) ++m_zone_start[m_parent[v] + 1];
    for (int v = 0; v < m_count; ++v) m_zone_start[v + 1] += m_zone_start[v];
    m_fill.assign(m_zone_start.begin(), m_zone_start.end() - 1);
    m_order.resize(static_cast<std::size_t>(m_count));
    for (int v = 0; v < m_count; ++v) m_order[m_fill[m_parent[v]]++] = v;
    int zones = 0;
    for (int r = 0; r < m_count; ++r) zones += m_zone_start[r + 1] - m_zone_start[r] > 1;
    p.stats.impact_zones = zones;
    if (clear) return true;
    for (int r = 0; r < m_count; ++r) {
      if (m_zone_start[r + 1] - m_zone_start[r] < 2) continue;
      members.assign(m_order.begin() + m_zone_start[r], m_order.begin() + m_zone_start[r + 1]);
      rigidify(p, r, members);
    }
  }
  return false;
}

SelfContactStats SelfContact::resolve(double h, const Matrix3X& x_start, Matrix3X& x, Matrix3X& v,
                                      const VectorX& inv_mass) {
  if (x_start.cols() != m_count || x.cols() != m_count || v.cols() != m_count ||
      inv_mass.size() != m_count)
    throw std::invalid_argument(
        "self-contact: positions, velocities and inverse masses must "
        "have one entry per particle (" +
        std::to_string(m_count) + ")");
  if (!(h > 0) || !std::isfinite(h))
    throw std::invalid_argument("self-contact: the step must be positive and finite");
  if (!inv_mass.allFinite() || (inv_mass.array() < 0).any())
    throw std::invalid_argument("self-contact: inverse masses must be finite and >= 0");
  m_vbar = (x - x_start) / h;
  Pass p{h, x_start, inv_mass, *m_scratch.ptr, m_vbar, {}};
  // proximity impulses, collision impulses, then impact zones until collision free
  proximity_pass(p);
  int left = 1;
  for (int round = 0; round < m_params.ccd_iterations && left > 0; ++round)
    left = collision_round(p, true, false);
  if (left > 0) p.stats.resolved = zone_pass(p);
  // the fail-safe's fail-safe: the free vertices keep their start positions
  if (!p.stats.resolved)
    for (int i = 0; i < m_count; ++i)
      if (inv_mass[i] > 0) m_vbar.col(i).setZero();
  v += m_vbar - (x - x_start) / h;
  x = x_start + h * m_vbar;
  return p.stats;
}

}  // namespace cloth
