#include "cloth/model/triangle_mesh.hpp"

#include <Eigen/Geometry>
#include <algorithm>

namespace cloth {

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
