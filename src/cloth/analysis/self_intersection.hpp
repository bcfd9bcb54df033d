#pragma once
/// @file self_intersection.hpp
/// How far a cloth has passed through itself, measured from positions and triangles alone,
/// the same way for every engine.
///
/// crossings: edge-triangle pairs sharing no vertex where the edge properly crosses the
/// triangle's interior, decided with exact orientation signs (exact_orient.hpp): edge (p, q)
/// crosses triangle (a, b, c) when orient3d(a, b, c, p) and orient3d(a, b, c, q) are nonzero
/// with opposite signs and orient3d(p, q, a, b), orient3d(p, q, b, c), orient3d(p, q, c, a)
/// are nonzero with one sign. Touching (any sign zero) and coplanar pairs are not crossings.
///
/// min_distance: the smallest vertex-triangle or edge-edge distance between elements more than
/// two rings apart (graph distance over mesh edges: a vertex-triangle pair is left out when the
/// vertex is within distance 2 of one of the triangle's vertices, an edge-edge pair when an
/// endpoint of one is within distance 2 of an endpoint of the other), capped at the cutoff.
///
/// Cost: a uniform spatial hash of the triangles' boxes, with cells 1.5 times the cutoff or
/// 1.5 times the median current edge length (the median, so a few blown-up edges do not coarsen
/// it), addressed by hashing cell coordinates into a table of about twice the triangle count, so
/// memory does not depend on the coordinates. A box spanning more than kMaxCellsPerBox cells is
/// not hashed: such a triangle is checked by every query, and such a query checks every
/// triangle. Every bucket entry read and cell addressed is one unit of work; past
/// work_budget() units the measurement stops and says so (complete = false), which only a
/// blown-up state (every element overlapping every other) reaches. Before the exact signs, a
/// pair is dropped when doubles already prove it misses (both endpoints well on one side of the
/// plane, or the two separated inside the plane): that only skips work, never decides a
/// crossing, and spares the slow exact path on the nearly coplanar neighbours of a flat sheet.

#include <array>
#include <vector>

#include "cloth/model/types.hpp"

namespace cloth {

/// Largest number of hash cells one box is entered into or looked up in.
constexpr int kMaxCellsPerBox = 64;

/// One frame's self-intersection figures.
struct SelfIntersection {
  int crossings = 0;        // edge-triangle pairs sharing no vertex where the edge properly crosses
                            // the triangle's interior; -1 when a position is not finite
  double min_distance = 0;  // m, smallest vertex-triangle or edge-edge distance between elements
                            // more than two rings apart, capped at the cutoff; NaN when not finite
  bool complete = true;     // false when the work budget ran out (a blown-up state): crossings is
                            // then a lower bound, min_distance an upper bound and the crossing
                            // triangles a part of them
  long long work = 0;       // units of work done (cells addressed, bucket entries read)
};

/// Counts crossings and the smallest non-adjacent distance of one triangle mesh, frame by frame.
class SelfIntersectionMeter {
 public:
  /// triangles over vertex_count vertices; cutoff (m) > 0 caps min_distance (the harness passes
  /// half the mean rest edge length). Precomputes the unique edges and the 2-ring exclusion.
  /// Throws std::invalid_argument on an index out of range, a triangle repeating a vertex or a
  /// cutoff that is not positive and finite.
  SelfIntersectionMeter(int vertex_count, std::vector<Triangle> triangles, double cutoff);

  /// x: 3 by #P positions (m). If crossing_triangles is given, it receives the sorted indices of
  /// every triangle pierced by an edge and every triangle holding a piercing edge.
  /// Throws std::invalid_argument when x does not have vertex_count columns.
  SelfIntersection measure(const Matrix3X& x, std::vector<int>* crossing_triangles = nullptr) const;

  /// True when vertices v and w are at most two mesh edges apart (v == w included).
  bool within_two_rings(int v, int w) const;

  /// The unique edges (lower index first), sorted.
  const std::vector<std::array<int, 2>>& edges() const { return m_edges; }
  const std::vector<Triangle>& triangles() const { return m_triangles; }
  int vertex_count() const { return m_vertex_count; }
  double cutoff() const { return m_cutoff; }
  /// Units of work after which measure() stops: 1024 per element (vertex, edge, triangle)
  /// plus 2^22.
  long long work_budget() const { return m_work_budget; }

 private:
  struct Grid;
  struct Search;
  void build_rings();
  bool mark_ring(std::vector<int>& marks, int query, int v) const;
  void edge_triangle(Search& s, int e, int t, bool marked, bool want_cross) const;
  void vertex_triangle(Search& s, int v, const std::vector<int>& marks, int query, bool marked,
                       int t) const;
  void edge_pass(Search& s) const;
  void vertex_pass(Search& s) const;

  int m_vertex_count = 0;
  std::vector<Triangle> m_triangles;
  double m_cutoff = 0;
  std::vector<std::array<int, 2>> m_edges;      // #E unique edges (lo, hi)
  std::vector<std::array<int, 3>> m_tri_edges;  // #T: edge k joins vertices k and k + 1
  std::vector<char> m_owned;  // #T: bit k set when the triangle is edge k's first triangle
  std::vector<char> m_hosts;  // #E: bit k set when the edge is its end k's first edge
  std::vector<std::array<int, 2>> m_edge_tris;  // #E: the (one or two) triangles of an edge, -1
  std::vector<int> m_adj_start, m_adj;          // vertex neighbours, CSR, sorted
  std::vector<int> m_ring_start, m_ring;        // vertices within two rings, CSR, sorted;
  std::vector<char> m_has_ring;                 // ... kept only where that set is small
  long long m_work_budget = 0;
};

/// The meter of a cloth whose rest shape is x0 (3 by #P, m): its distances capped at half the
/// mean rest edge length (layers closer than that are near contact; a larger cap costs more to
/// search), or at 1 m when that length is not positive and finite.
SelfIntersectionMeter rest_shape_meter(const Matrix3X& x0, const std::vector<Triangle>& triangles);

}  // namespace cloth
