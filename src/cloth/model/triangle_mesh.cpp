#include "cloth/model/triangle_mesh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <set>

namespace cloth {

namespace {

/// The pair (a, b) with the lower index first.
std::array<int, 2> ordered(int a, int b) {
  return {std::min(a, b), std::max(a, b)};
}

}  // namespace

LatticeLinks lattice_links(const TriangleMesh& mesh) {
  // sides between consecutive present corners, diagonals between opposite present ones
  std::set<std::array<int, 2>> sides, diagonals;
  for (const auto& c : mesh.cells) {
    for (int k = 0; k < 4; ++k)
      if (c[k] >= 0 && c[(k + 1) % 4] >= 0) sides.insert(ordered(c[k], c[(k + 1) % 4]));
    for (int k = 0; k < 2; ++k)
      if (c[k] >= 0 && c[k + 2] >= 0) diagonals.insert(ordered(c[k], c[k + 2]));
  }
  // a vertex's sides pointing opposite ways join its two neighbours along one yarn
  std::vector<std::vector<int>> next(size_t(mesh.vertex_count()));
  for (const auto& [a, b] : sides) {
    next[size_t(a)].push_back(b);
    next[size_t(b)].push_back(a);
  }
  std::set<std::array<int, 2>> bends;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    for (size_t i = 0; i < next[size_t(v)].size(); ++i)
      for (size_t j = i + 1; j < next[size_t(v)].size(); ++j) {
        const int a = next[size_t(v)][i], b = next[size_t(v)][j];
        const Vector3 da = mesh.x.col(a) - mesh.x.col(v), db = mesh.x.col(b) - mesh.x.col(v);
        if (da.dot(db) < -0.99 * da.norm() * db.norm()) bends.insert(ordered(a, b));
      }
  LatticeLinks out;
  out.structural.assign(sides.begin(), sides.end());
  out.shear.assign(diagonals.begin(), diagonals.end());
  out.bend.assign(bends.begin(), bends.end());
  return out;
}

MeshEdges mesh_edges(const TriangleMesh& mesh) {
  // every triangle side as (low, high, triangle, opposite vertex), sorted so equal edges meet
  std::vector<std::array<int, 4>> sides;
  sides.reserve(3 * mesh.triangles.size());
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
      sides.push_back({std::min(a, b), std::max(a, b), t, c});
    }
  }
  std::sort(sides.begin(), sides.end());

  // one edge per run of equal (low, high); a bend pair where the run holds two triangles
  MeshEdges out;
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j][0] == sides[i][0] && sides[j][1] == sides[i][1]) ++j;
    out.edges.push_back({sides[i][0], sides[i][1]});
    if (j - i == 2) out.bend_pairs.push_back({sides[i][3], sides[i + 1][3]});
    i = j;
  }
  return out;
}

double triangle_area(const TriangleMesh& mesh, int t) {
  const auto& tri = mesh.triangles[t];
  const Vector3 a = mesh.x.col(tri[0]);
  const Vector3 e1 = Vector3(mesh.x.col(tri[1])) - a;
  const Vector3 e2 = Vector3(mesh.x.col(tri[2])) - a;
  return 0.5 * e1.cross(e2).norm();
}

VectorX lumped_masses(const TriangleMesh& mesh, double areal_density) {
  VectorX m = VectorX::Zero(mesh.vertex_count());
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const double share = areal_density * triangle_area(mesh, t) / 3.0;
    for (int v : mesh.triangles[t]) m[v] += share;
  }
  return m;
}

double mesh_area(const TriangleMesh& mesh) {
  double sum = 0;
  for (int t = 0; t < mesh.triangle_count(); ++t) sum += triangle_area(mesh, t);
  return sum;
}

}  // namespace cloth
