#include "cloth/analysis/self_intersection.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "cloth/analysis/element_distance.hpp"
#include "cloth/analysis/exact_orient.hpp"

namespace cloth {
namespace {

/// Cell coordinates are clamped to +-2^40 so huge positions stay integers (clamping is
/// monotone: boxes that overlap still share a cell).
constexpr double kCellClamp = 1099511627776.0;
/// Largest 2-ring kept as a sorted list per vertex; past it (a vertex of high valence or next
/// to one) the test intersects neighbour lists instead, so memory stays linear.
constexpr int kRingCap = 256;
constexpr long long kWorkPerElement = 1024;
constexpr long long kWorkFloor = 1LL << 22;

struct Aabb {
  Vector3 lo, hi;
};

Aabb box_of(const Vector3& a, const Vector3& b) {
  return {a.cwiseMin(b), a.cwiseMax(b)};
}

bool overlap(const Aabb& a, const Aabb& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

/// True when the boxes come closer than r (> 0): the Euclidean distance between them, which no
/// pair of their points undercuts, is below r. Squared, with an early exit per axis.
inline bool closer_than(const Aabb& a, const Aabb& b, double r) {
  double gap2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double gap = std::max(a.lo[k] - b.hi[k], b.lo[k] - a.hi[k]);
    if (gap >= r) return false;
    if (gap > 0) gap2 += gap * gap;
  }
  // (a cutoff so large its square overflows keeps every pair)
  return gap2 < r * r || !std::isfinite(r * r);
}

std::int64_t cell_of(double q) {
  return static_cast<std::int64_t>(std::clamp(std::floor(q), -kCellClamp, kCellClamp));
}

std::size_t bucket_of(std::int64_t i, std::int64_t j, std::int64_t k, std::size_t mask) {
  std::uint64_t h = std::uint64_t(i) * 0x9E3779B97F4A7C15ull;
  h ^= std::uint64_t(j) * 0xC2B2AE3D27D4EB4Full;
  h ^= std::uint64_t(k) * 0x165667B19E3779F9ull;
  h ^= h >> 31;
  return static_cast<std::size_t>(h) & mask;
}

/// The cells a box inflated by r covers, or too_many when more than kMaxCellsPerBox.
struct CellRange {
  std::int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool too_many = false;
};

CellRange cell_range(const Aabb& b, double r, double h) {
  CellRange c;
  std::int64_t count = 1;
  for (int k = 0; k < 3; ++k) {
    c.lo[k] = cell_of((b.lo[k] - r) / h);
    c.hi[k] = cell_of((b.hi[k] + r) / h);
    count *= std::min<std::int64_t>(c.hi[k] - c.lo[k] + 1, kMaxCellsPerBox + 1);
    count = std::min<std::int64_t>(count, kMaxCellsPerBox + 1);
  }
  c.too_many = count > kMaxCellsPerBox;
  return c;
}

template <class F>
void for_each_cell(const CellRange& c, F&& f) {
  for (std::int64_t i = c.lo[0]; i <= c.hi[0]; ++i)
    for (std::int64_t j = c.lo[1]; j <= c.hi[1]; ++j)
      for (std::int64_t k = c.lo[2]; k <= c.hi[2]; ++k) f(i, j, k);
}

/// Margin of the floating-point rejections below, relative to the extent cubed (or squared
/// times the axis length): their evaluation errs by a few 1e-16 of that, so a value beyond the
/// margin has its sign for certain. Outside [1e-90, 1e90] extents they are skipped (underflow,
/// overflow) and the exact signs decide alone.
constexpr double kRejectMargin = 1e-10;

/// True when projections onto the axis separate the segment from the triangle by more than the
/// margin (any axis: separated projections prove the sets disjoint).
bool separated_along(const Vector3& axis, const Vector3 (&seg)[2], const Vector3 (&tri)[3],
                     double extent) {
  const double s0 = axis.dot(seg[0]), s1 = axis.dot(seg[1]);
  const double t0 = axis.dot(tri[0]), t1 = axis.dot(tri[1]), t2 = axis.dot(tri[2]);
  const double margin = kRejectMargin * axis.cwiseAbs().sum() * extent;
  return std::min(s0, s1) > std::max({t0, t1, t2}) + margin ||
         std::max(s0, s1) < std::min({t0, t1, t2}) - margin;
}

/// True when the edge certainly misses the triangle, decided in doubles: both endpoints well on
/// one side of its plane, or (nearly coplanar neighbours in a flat or tilted sheet, whose exact
/// signs are slow) separated inside the plane along an edge normal or the segment's normal.
bool certainly_misses(const Vector3& p, const Vector3& q, const Vector3& a, const Vector3& b,
                      const Vector3& c) {
  const Vector3 tri[3] = {Vector3::Zero(), b - a, c - a};
  const Vector3 seg[2] = {p - a, q - a};
  const double extent = std::max({tri[1].cwiseAbs().maxCoeff(), tri[2].cwiseAbs().maxCoeff(),
                                  seg[0].cwiseAbs().maxCoeff(), seg[1].cwiseAbs().maxCoeff()});
  if (!(extent >= 1e-90 && extent <= 1e90)) return false;
  const Vector3 n = tri[1].cross(tri[2]);
  const double side = kRejectMargin * extent * extent * extent;
  const double dp = n.dot(seg[0]), dq = n.dot(seg[1]);
  if ((dp > side && dq > side) || (dp < -side && dq < -side)) return true;
  const double extent2 = extent * extent;
  if (separated_along(n.cross(tri[1]), seg, tri, extent2) ||
      separated_along(n.cross(tri[2] - tri[1]), seg, tri, extent2) ||
      separated_along(n.cross(tri[2]), seg, tri, extent2))
    return true;
  return separated_along(n.cross(seg[1] - seg[0]), seg, tri, extent2);
}

/// The five exact signs of the crossing rule (see the header).
bool edge_crosses_triangle(const Vector3& p, const Vector3& q, const Vector3& a, const Vector3& b,
                           const Vector3& c) {
  // a triangle in an axis plane with an endpoint in it (a flat cloth at rest): a zero sign
  for (int r = 0; r < 3; ++r)
    if (a[r] == b[r] && a[r] == c[r] && (p[r] == a[r] || q[r] == a[r])) return false;
  if (certainly_misses(p, q, a, b, c)) return false;
  const int sp = orient3d_sign(a, b, c, p);
  if (sp == 0 || orient3d_sign(a, b, c, q) != -sp) return false;
  const int s = orient3d_sign(p, q, a, b);
  return s != 0 && orient3d_sign(p, q, b, c) == s && orient3d_sign(p, q, c, a) == s;
}

/// Median edge length of the current positions (0 without edges), robust to a few huge ones.
double median_edge_length(const std::vector<std::array<int, 2>>& edges, const Matrix3X& x) {
  if (edges.empty()) return 0.0;
  std::vector<double> len(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e)
    len[e] = (x.col(edges[e][0]) - x.col(edges[e][1])).norm();
  auto mid = len.begin() + static_cast<std::ptrdiff_t>(len.size() / 2);
  std::nth_element(len.begin(), mid, len.end());
  return *mid;
}

}  // namespace

/// The triangles' boxes hashed into cells of size h.
struct SelfIntersectionMeter::Grid {
  double h = 1;
  std::size_t mask = 0;
  std::vector<Aabb> tri_box;     // #T
  std::vector<int> start, item;  // bucket b holds item[start[b] .. start[b + 1])
  std::vector<int> big;          // triangles spanning too many cells, checked by every query
};

/// One measurement's state: positions, grid, running results and the work counter.
struct SelfIntersectionMeter::Search {
  const Matrix3X& x;
  Grid grid;
  std::vector<int> stamp;        // #T: the last query that visited each triangle
  std::vector<int> near;         // #P: the last query whose 2-rings hold each vertex
  std::vector<int> near_end[2];  // #P each: the last edge whose end k's 2-ring holds the vertex
  double best = 0;               // smallest distance so far (m)
  int crossings = 0;
  long long work = 0;
  long long budget = 0;
  bool exhausted = false;
  std::vector<int>* crossing_triangles = nullptr;

  Vector3 p(int v) const { return x.col(v); }

  /// Calls f(t) once for every triangle whose box may overlap the box b inflated by r;
  /// false when the budget ran out.
  template <class F>
  bool visit(const Aabb& b, double r, int query, F&& f) {
    const CellRange c = cell_range(b, r, grid.h);
    const auto once = [&](int t) {
      ++work;
      if (stamp[t] == query) return;
      stamp[t] = query;
      f(t);
    };
    if (c.too_many) {
      // a query box this large checks every triangle
      for (int t = 0; t < static_cast<int>(stamp.size()) && !exhausted; ++t) {
        once(t);
        exhausted = work > budget;
      }
      return !exhausted;
    }
    for_each_cell(c, [&](std::int64_t i, std::int64_t j, std::int64_t k) {
      if (exhausted) return;
      ++work;
      const std::size_t bucket = bucket_of(i, j, k, grid.mask);
      for (int n = grid.start[bucket]; n < grid.start[bucket + 1]; ++n) once(grid.item[n]);
      exhausted = work > budget;
    });
    for (std::size_t n = 0; n < grid.big.size() && !exhausted; ++n) {
      once(grid.big[n]);
      exhausted = work > budget;
    }
    return !exhausted;
  }
};

SelfIntersectionMeter::SelfIntersectionMeter(int vertex_count, std::vector<Triangle> triangles,
                                             double cutoff)
    : m_vertex_count(vertex_count), m_triangles(std::move(triangles)), m_cutoff(cutoff) {
  if (vertex_count < 0) throw std::invalid_argument("self-intersection: negative vertex count");
  if (!(cutoff > 0) || !std::isfinite(cutoff))
    throw std::invalid_argument("self-intersection: cutoff must be positive and finite, got " +
                                std::to_string(cutoff));
  // the unique edges, each with its triangles
  std::vector<std::array<int, 4>> half;  // (lo, hi, triangle, side k)
  for (std::size_t t = 0; t < m_triangles.size(); ++t) {
    const Triangle& tri = m_triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= vertex_count)
        throw std::invalid_argument("self-intersection: triangle " + std::to_string(t) +
                                    " has a vertex index out of range");
      if (tri[k] == tri[(k + 1) % 3])
        throw std::invalid_argument("self-intersection: triangle " + std::to_string(t) +
                                    " repeats a vertex");
      const int a = tri[k], b = tri[(k + 1) % 3];
      half.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t), k});
    }
  }
  std::sort(half.begin(), half.end());
  m_tri_edges.assign(m_triangles.size(), {-1, -1, -1});
  for (const auto& h : half) {
    if (m_edges.empty() || m_edges.back() != std::array<int, 2>{h[0], h[1]}) {
      m_edges.push_back({h[0], h[1]});
      m_edge_tris.push_back({h[2], -1});
    } else if (m_edge_tris.back()[1] < 0) {
      m_edge_tris.back()[1] = h[2];
    }
    m_tri_edges[h[2]][h[3]] = static_cast<int>(m_edges.size()) - 1;
  }
  // the sides each triangle owns (it is the edge's first triangle), for edge-edge pairs
  m_owned.assign(m_triangles.size(), 0);
  for (std::size_t t = 0; t < m_triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (m_edge_tris[m_tri_edges[t][k]][0] == static_cast<int>(t)) m_owned[t] |= char(1 << k);
  // the edge that measures each vertex's distances: its first edge
  m_hosts.assign(m_edges.size(), 0);
  std::vector<char> hosted(static_cast<std::size_t>(vertex_count), 0);
  for (std::size_t e = 0; e < m_edges.size(); ++e)
    for (int k = 0; k < 2; ++k)
      if (!hosted[m_edges[e][k]]) {
        hosted[m_edges[e][k]] = 1;
        m_hosts[e] |= char(1 << k);
      }
  build_rings();
  const auto elements = static_cast<long long>(vertex_count) +
                        static_cast<long long>(m_edges.size() + m_triangles.size());
  m_work_budget = kWorkPerElement * elements + kWorkFloor;
}

void SelfIntersectionMeter::build_rings() {
  // neighbour lists from the edges (sorted, since the edges are)
  const int n = m_vertex_count;
  m_adj_start.assign(n + 1, 0);
  for (const auto& e : m_edges) {
    ++m_adj_start[e[0] + 1];
    ++m_adj_start[e[1] + 1];
  }
  for (int v = 0; v < n; ++v) m_adj_start[v + 1] += m_adj_start[v];
  m_adj.assign(m_adj_start[n], 0);
  std::vector<int> fill(m_adj_start.begin(), m_adj_start.end() - 1);
  for (const auto& e : m_edges) {
    m_adj[fill[e[0]]++] = e[1];
    m_adj[fill[e[1]]++] = e[0];
  }
  for (int v = 0; v < n; ++v)
    std::sort(m_adj.begin() + m_adj_start[v], m_adj.begin() + m_adj_start[v + 1]);
  // the 2-ring of each vertex, kept where it is small
  m_ring_start.assign(n + 1, 0);
  m_has_ring.assign(n, 0);
  std::vector<int> ring;
  for (int v = 0; v < n; ++v) {
    std::size_t bound = 1;
    for (int a = m_adj_start[v]; a < m_adj_start[v + 1]; ++a)
      bound += 1 + static_cast<std::size_t>(m_adj_start[m_adj[a] + 1] - m_adj_start[m_adj[a]]);
    if (bound <= static_cast<std::size_t>(kRingCap)) {
      ring.assign(1, v);
      for (int a = m_adj_start[v]; a < m_adj_start[v + 1]; ++a) {
        const int u = m_adj[a];
        ring.push_back(u);
        ring.insert(ring.end(), m_adj.begin() + m_adj_start[u], m_adj.begin() + m_adj_start[u + 1]);
      }
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      m_ring.insert(m_ring.end(), ring.begin(), ring.end());
      m_has_ring[v] = 1;
    }
    m_ring_start[v + 1] = static_cast<int>(m_ring.size());
  }
}

bool SelfIntersectionMeter::within_two_rings(int v, int w) const {
  if (v == w) return true;
  const auto has = [](const std::vector<int>& list, int from, int to, int value) {
    return std::binary_search(list.begin() + from, list.begin() + to, value);
  };
  if (m_has_ring[v]) return has(m_ring, m_ring_start[v], m_ring_start[v + 1], w);
  if (m_has_ring[w]) return has(m_ring, m_ring_start[w], m_ring_start[w + 1], v);
  // both of high valence: a direct edge or a common neighbour
  if (has(m_adj, m_adj_start[v], m_adj_start[v + 1], w)) return true;
  const bool v_smaller = m_adj_start[v + 1] - m_adj_start[v] <= m_adj_start[w + 1] - m_adj_start[w];
  const int small = v_smaller ? v : w, large = v_smaller ? w : v;
  for (int a = m_adj_start[small]; a < m_adj_start[small + 1]; ++a)
    if (has(m_adj, m_adj_start[large], m_adj_start[large + 1], m_adj[a])) return true;
  return false;
}

bool SelfIntersectionMeter::mark_ring(std::vector<int>& marks, int query, int v) const {
  if (!m_has_ring[v]) return false;
  for (int n = m_ring_start[v]; n < m_ring_start[v + 1]; ++n) marks[m_ring[n]] = query;
  return true;
}

void SelfIntersectionMeter::edge_triangle(Search& s, int e, int t, bool marked,
                                          bool want_cross) const {
  const int p = m_edges[e][0], q = m_edges[e][1];
  const Vector3 xp = s.p(p), xq = s.p(q);
  const Aabb eb = box_of(xp, xq);
  const Triangle& tri = m_triangles[t];
  const Aabb& tb = s.grid.tri_box[t];
  const auto near = [&](int u) {
    return marked ? s.near[u] == e : within_two_rings(p, u) || within_two_rings(q, u);
  };
  // the crossing, for a triangle sharing no vertex with the edge
  const bool shares =
      tri[0] == p || tri[1] == p || tri[2] == p || tri[0] == q || tri[1] == q || tri[2] == q;
  if (want_cross && !shares && overlap(eb, tb) &&
      edge_crosses_triangle(xp, xq, s.p(tri[0]), s.p(tri[1]), s.p(tri[2]))) {
    ++s.crossings;
    if (s.crossing_triangles) {
      s.crossing_triangles->push_back(t);
      for (int owner : m_edge_tris[e])
        if (owner >= 0) s.crossing_triangles->push_back(owner);
    }
  }
  // edge-edge distances to the triangle's edges of higher index, each pair once (through
  // the first triangle of the other edge)
  if (!(s.best > 0) || !closer_than(eb, tb, s.best)) return;
  if (near(tri[0]) && near(tri[1]) && near(tri[2])) return;
  for (int k = 0; k < 3; ++k) {
    // (endpoints in the edge's order, lower index first)
    const int u = std::min(tri[k], tri[(k + 1) % 3]), w = std::max(tri[k], tri[(k + 1) % 3]);
    if (!(m_owned[t] >> k & 1) || m_tri_edges[t][k] <= e || near(u) || near(w)) continue;
    const Vector3 xu = s.p(u), xw = s.p(w);
    if (!closer_than(eb, box_of(xu, xw), s.best)) continue;
    const double d = segment_segment_distance(xp, xq, xu, xw);
    if (d < s.best) s.best = d;
  }
}

void SelfIntersectionMeter::vertex_triangle(Search& s, int v, const std::vector<int>& marks,
                                            int query, bool marked, int t) const {
  const Triangle& tri = m_triangles[t];
  const auto near = [&](int u) { return marked ? marks[u] == query : within_two_rings(v, u); };
  if (!(s.best > 0) || near(tri[0]) || near(tri[1]) || near(tri[2])) return;
  const Vector3 xv = s.p(v);
  if (!closer_than(Aabb{xv, xv}, s.grid.tri_box[t], s.best)) return;
  const double d = point_triangle_distance(xv, s.p(tri[0]), s.p(tri[1]), s.p(tri[2]));
  if (d < s.best) s.best = d;
}

void SelfIntersectionMeter::edge_pass(Search& s) const {
  for (int e = 0; e < static_cast<int>(m_edges.size()) && !s.exhausted; ++e) {
    const int p = m_edges[e][0], q = m_edges[e][1];
    const Vector3 xp = s.p(p), xq = s.p(q);
    const Aabb eb = box_of(xp, xq);
    // a collapsed edge crosses nothing; with best == 0 no distance can improve
    const bool want_cross = xp != xq;
    if (!want_cross && !(s.best > 0)) continue;
    // the vertices within two rings of p or q, marked for O(1) look-ups where the rings are kept
    const bool marked = mark_ring(s.near, e, p) & mark_ring(s.near, e, q);
    // the ends whose vertex-triangle distances this edge measures (it is their first edge):
    // every triangle within best of an end is within best of the edge, so its query finds them
    const int hosts = m_hosts[e];
    bool end_marked[2] = {false, false};
    for (int k = 0; k < 2; ++k)
      if (hosts >> k & 1) end_marked[k] = mark_ring(s.near_end[k], e, m_edges[e][k]);
    s.visit(eb, s.best, e, [&](int t) {
      // a triangle whose box neither overlaps the edge's nor comes within best of it can
      // neither be crossed nor come closer to the edge or its ends
      const Aabb& tb = s.grid.tri_box[t];
      if (!overlap(eb, tb) && !(s.best > 0 && closer_than(eb, tb, s.best))) return;
      edge_triangle(s, e, t, marked, want_cross);
      for (int k = 0; k < 2; ++k)
        if (hosts >> k & 1) vertex_triangle(s, m_edges[e][k], s.near_end[k], e, end_marked[k], t);
    });
  }
}

void SelfIntersectionMeter::vertex_pass(Search& s) const {
  // only vertices on no edge: the edge pass measured every other one
  const int offset = static_cast<int>(m_edges.size());
  for (int v = 0; v < m_vertex_count && !s.exhausted && s.best > 0; ++v) {
    if (m_adj_start[v + 1] > m_adj_start[v]) continue;
    const Vector3 xv = s.p(v);
    const bool marked = mark_ring(s.near, offset + v, v);
    s.visit(Aabb{xv, xv}, s.best, offset + v,
            [&](int t) { vertex_triangle(s, v, s.near, offset + v, marked, t); });
  }
}

SelfIntersection SelfIntersectionMeter::measure(const Matrix3X& x,
                                                std::vector<int>* crossing_triangles) const {
  if (x.cols() != m_vertex_count)
    throw std::invalid_argument("self-intersection: " + std::to_string(x.cols()) +
                                " positions for a mesh of " + std::to_string(m_vertex_count) +
                                " vertices");
  if (crossing_triangles) crossing_triangles->clear();
  SelfIntersection r;
  if (!x.allFinite()) {
    r.crossings = -1;
    r.min_distance = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  Search s{x,
           Grid{},
           std::vector<int>(m_triangles.size(), -1),
           std::vector<int>(static_cast<std::size_t>(m_vertex_count), -1),
           {std::vector<int>(static_cast<std::size_t>(m_vertex_count), -1),
            std::vector<int>(static_cast<std::size_t>(m_vertex_count), -1)},
           m_cutoff,
           0,
           0,
           m_work_budget,
           false,
           crossing_triangles};
  // cells: the cutoff or the median edge length, whichever is larger (finite in any case)
  Grid& g = s.grid;
  g.h = 1.5 * std::max(m_cutoff, median_edge_length(m_edges, x));
  if (!std::isfinite(g.h)) g.h = std::numeric_limits<double>::max();
  const std::size_t tri_count = m_triangles.size();
  std::size_t table = 1;
  while (table < 2 * tri_count) table *= 2;
  g.mask = table - 1;
  g.tri_box.resize(tri_count);
  std::vector<CellRange> ranges(tri_count);
  g.start.assign(table + 1, 0);
  // count the entries of each bucket, then fill them
  for (std::size_t t = 0; t < tri_count; ++t) {
    const Triangle& tri = m_triangles[t];
    Aabb b = box_of(x.col(tri[0]), x.col(tri[1]));
    b.lo = b.lo.cwiseMin(Vector3(x.col(tri[2])));
    b.hi = b.hi.cwiseMax(Vector3(x.col(tri[2])));
    g.tri_box[t] = b;
    ranges[t] = cell_range(b, 0.0, g.h);
    if (ranges[t].too_many) {
      g.big.push_back(static_cast<int>(t));
      continue;
    }
    for_each_cell(ranges[t], [&](std::int64_t i, std::int64_t j, std::int64_t k) {
      ++g.start[bucket_of(i, j, k, g.mask) + 1];
      ++s.work;
    });
  }
  for (std::size_t b = 0; b < table; ++b) g.start[b + 1] += g.start[b];
  g.item.resize(static_cast<std::size_t>(g.start[table]));
  std::vector<int> fill(g.start.begin(), g.start.end() - 1);
  for (std::size_t t = 0; t < tri_count; ++t) {
    if (ranges[t].too_many) continue;
    for_each_cell(ranges[t], [&](std::int64_t i, std::int64_t j, std::int64_t k) {
      g.item[static_cast<std::size_t>(fill[bucket_of(i, j, k, g.mask)]++)] = static_cast<int>(t);
    });
  }
  // edges against triangles (crossings, edge-edge), then vertices against triangles
  edge_pass(s);
  vertex_pass(s);
  r.crossings = s.crossings;
  r.min_distance = std::min(s.best, m_cutoff);
  r.complete = !s.exhausted;
  r.work = s.work;
  if (crossing_triangles) {
    std::sort(crossing_triangles->begin(), crossing_triangles->end());
    crossing_triangles->erase(std::unique(crossing_triangles->begin(), crossing_triangles->end()),
                              crossing_triangles->end());
  }
  return r;
}

SelfIntersectionMeter rest_shape_meter(const Matrix3X& x0, const std::vector<Triangle>& triangles) {
  // the mean rest length of the triangles' edges (each interior edge counted twice)
  double sum = 0;
  for (const Triangle& tri : triangles)
    for (int k = 0; k < 3; ++k) sum += (x0.col(tri[(k + 1) % 3]) - x0.col(tri[k])).norm();
  const double half =
      triangles.empty() ? 0.0 : 0.5 * (sum / (3.0 * static_cast<double>(triangles.size())));
  return SelfIntersectionMeter(static_cast<int>(x0.cols()), triangles,
                               half > 0 && std::isfinite(half) ? half : 1.0);
}

}  // namespace cloth
