#include "cloth/model/mesh_check.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Geometry>

namespace cloth {

namespace {

using Kind = MeshProblemKind;

std::string str(int i) {
  return std::to_string(i);
}

/// True when triangle t's corners are in range and distinct: it takes part in the edge checks.
bool usable(const std::array<int, 3>& tri, int nv) {
  for (int v : tri)
    if (v < 0 || v >= nv) return false;
  return tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2];
}

void check_vertices(const TriangleMesh& mesh, std::vector<MeshProblem>& out) {
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (!mesh.x.col(v).allFinite())
      out.push_back({Kind::non_finite_vertex, v, -1, -1, -1,
                     "vertex " + str(v) + " has a coordinate that is not a finite number"});
}

void check_triangles(const TriangleMesh& mesh, std::vector<MeshProblem>& out) {
  const int nv = mesh.vertex_count();
  // indices out of range first: such a triangle has no area to look at
  for (int t = 0; t < mesh.triangle_count(); ++t)
    for (int v : mesh.triangles[t])
      if (v < 0 || v >= nv) {
        out.push_back(
            {Kind::index_out_of_range, v, -1, t, -1,
             "triangle " + str(t) + " names vertex " + str(v) + ", outside 0.." + str(nv - 1)});
        break;
      }
  // repeated corners, then areas at most kDegenerateAreaRatio of the longest edge squared
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const auto& tri = mesh.triangles[t];
    if (std::any_of(tri.begin(), tri.end(), [&](int v) { return v < 0 || v >= nv; })) continue;
    const std::string names =
        " (vertices " + str(tri[0]) + ", " + str(tri[1]) + ", " + str(tri[2]) + ")";
    if (!usable(tri, nv)) {
      out.push_back({Kind::degenerate_triangle, -1, -1, t, -1,
                     "triangle " + str(t) + names + " repeats a vertex"});
      continue;
    }
    const Vector3 a = mesh.x.col(tri[0]), b = mesh.x.col(tri[1]), c = mesh.x.col(tri[2]);
    // a corner that is not finite is its vertex's problem (non_finite_vertex)
    if (!a.allFinite() || !b.allFinite() || !c.allFinite()) continue;
    const double longest =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    // coordinates past about 1e154 m: neither length nor area can be measured
    if (!std::isfinite(longest)) {
      out.push_back({Kind::oversized_triangle, -1, -1, t, -1,
                     "triangle " + str(t) + names + " has a side too long to measure"});
      continue;
    }
    if (0.5 * (b - a).cross(c - a).norm() <= kDegenerateAreaRatio * longest)
      out.push_back({Kind::degenerate_triangle, -1, -1, t, -1,
                     "triangle " + str(t) + names + " has zero area"});
  }
}

void check_edges(const TriangleMesh& mesh, std::vector<MeshProblem>& out) {
  // every side as (low, high, triangle, 1 when it runs low -> high), sorted so equal edges meet
  std::vector<std::array<int, 4>> sides;
  sides.reserve(3 * mesh.triangles.size());
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const auto& tri = mesh.triangles[t];
    if (!usable(tri, mesh.vertex_count())) continue;
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      sides.push_back({std::min(a, b), std::max(a, b), t, a < b ? 1 : 0});
    }
  }
  std::sort(sides.begin(), sides.end());

  // a run of more than two is non-manifold; a run of two running the same way is flipped
  std::vector<MeshProblem> flipped;
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j][0] == sides[i][0] && sides[j][1] == sides[i][1]) ++j;
    const int a = sides[i][0], b = sides[i][1];
    const std::string edge = "edge (" + str(a) + ", " + str(b) + ")";
    if (j - i > 2) {
      out.push_back({Kind::non_manifold_edge, a, b, sides[i + 2][2], -1,
                     edge + " is shared by " + str(static_cast<int>(j - i)) +
                         " triangles (at most two allowed)"});
    } else if (j - i == 2 && sides[i][3] == sides[i + 1][3]) {
      flipped.push_back({Kind::inconsistent_orientation, a, b, sides[i + 1][2], sides[i][2],
                         "triangles " + str(sides[i][2]) + " and " + str(sides[i + 1][2]) +
                             " run along their shared " + edge +
                             " the same way: their orientations disagree"});
    }
    i = j;
  }
  out.insert(out.end(), flipped.begin(), flipped.end());
}

/// Root of i in a union-find forest, halving paths on the way.
int root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

/// Number of fans around one vertex: its triangles joined where they share an edge through it.
/// corners holds (vertex, other end of an edge, triangle), sorted, all of one vertex.
int fan_count(const std::array<int, 3>* corners, std::size_t n) {
  std::vector<int> tris(n);
  for (std::size_t k = 0; k < n; ++k) tris[k] = corners[k][2];
  std::sort(tris.begin(), tris.end());
  tris.erase(std::unique(tris.begin(), tris.end()), tris.end());
  std::vector<int> parent(tris.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto local = [&](int t) {
    return static_cast<int>(std::lower_bound(tris.begin(), tris.end(), t) - tris.begin());
  };
  for (std::size_t k = 1; k < n; ++k)
    if (corners[k][1] == corners[k - 1][1])
      parent[root(parent, local(corners[k][2]))] = root(parent, local(corners[k - 1][2]));
  int fans = 0;
  for (std::size_t i = 0; i < tris.size(); ++i)
    fans += root(parent, static_cast<int>(i)) == static_cast<int>(i);
  return fans;
}

void check_fans(const TriangleMesh& mesh, std::vector<MeshProblem>& out) {
  // per corner: (vertex, the other end of each of its two edges, triangle), sorted by vertex
  std::vector<std::array<int, 3>> corners;
  corners.reserve(6 * mesh.triangles.size());
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const auto& tri = mesh.triangles[t];
    if (!usable(tri, mesh.vertex_count())) continue;
    for (int k = 0; k < 3; ++k) {
      corners.push_back({tri[k], tri[(k + 1) % 3], t});
      corners.push_back({tri[k], tri[(k + 2) % 3], t});
    }
  }
  std::sort(corners.begin(), corners.end());
  for (std::size_t i = 0; i < corners.size();) {
    std::size_t j = i;
    while (j < corners.size() && corners[j][0] == corners[i][0]) ++j;
    const int fans = fan_count(corners.data() + i, j - i);
    if (fans > 1)
      out.push_back({Kind::bowtie_vertex, corners[i][0], -1, -1, -1,
                     "vertex " + str(corners[i][0]) + " joins " + str(fans) +
                         " separate fans of triangles (a bowtie)"});
    i = j;
  }
}

void check_unused(const TriangleMesh& mesh, std::vector<MeshProblem>& out) {
  std::vector<char> used(mesh.vertex_count(), 0);
  for (const auto& tri : mesh.triangles)
    for (int v : tri)
      if (v >= 0 && v < mesh.vertex_count()) used[v] = 1;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (!used[v])
      out.push_back(
          {Kind::unused_vertex, v, -1, -1, -1, "vertex " + str(v) + " is in no triangle"});
}

}  // namespace

std::vector<MeshProblem> check_mesh(const TriangleMesh& mesh) {
  std::vector<MeshProblem> out;
  check_vertices(mesh, out);
  check_triangles(mesh, out);
  check_edges(mesh, out);
  check_fans(mesh, out);
  check_unused(mesh, out);
  // kinds in enum order, each in index order (the checks above emit each kind in order)
  std::stable_sort(out.begin(), out.end(), [](const MeshProblem& a, const MeshProblem& b) {
    return static_cast<int>(a.kind) < static_cast<int>(b.kind);
  });
  return out;
}

int error_count(const std::vector<MeshProblem>& problems) {
  return static_cast<int>(std::count_if(problems.begin(), problems.end(),
                                        [](const MeshProblem& p) { return p.is_error(); }));
}

}  // namespace cloth
