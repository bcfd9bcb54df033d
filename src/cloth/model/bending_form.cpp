#include "cloth/model/bending_form.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace cloth {

namespace {

/// One edge of the surface: half the sum of its opposite angles' cotangents, and how many
/// triangles share it (1 on the boundary).
struct EdgeWeight {
  double weight = 0;
  int triangles = 0;
};

/// The rest surface's cotangent weights, vertex areas and boundary vertices.
struct RestLaplacian {
  std::map<std::pair<int, int>, EdgeWeight> edges;  // by (lower, higher) particle
  std::vector<double> area;                         // #P barycentric areas (m^2)
  std::vector<char> boundary;                       // #P, 1 on a boundary edge
  std::vector<char> used;                           // #P, 1 in some triangle
};

RestLaplacian rest_laplacian(const Matrix3X& x0, const std::vector<Triangle>& triangles) {
  const auto n = static_cast<size_t>(x0.cols());
  RestLaplacian l;
  l.area.assign(n, 0.0);
  l.boundary.assign(n, 0);
  l.used.assign(n, 0);
  // each corner's cotangent goes to the edge across from it
  for (const Triangle& t : triangles) {
    const double twice_area =
        (x0.col(t[1]) - x0.col(t[0])).cross(x0.col(t[2]) - x0.col(t[0])).norm();
    if (!(twice_area > 0)) throw std::invalid_argument("hinge bending: a triangle has no area");
    for (int k = 0; k < 3; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)], c = t[size_t((k + 2) % 3)];
      const double cot = (x0.col(a) - x0.col(c)).dot(x0.col(b) - x0.col(c)) / twice_area;
      EdgeWeight& e = l.edges[{std::min(a, b), std::max(a, b)}];
      e.weight += 0.5 * cot;
      e.triangles += 1;
      l.area[size_t(a)] += twice_area / 6.0;
      l.used[size_t(a)] = 1;
    }
  }
  for (const auto& [ab, e] : l.edges)
    if (e.triangles == 1) l.boundary[size_t(ab.first)] = l.boundary[size_t(ab.second)] = 1;
  return l;
}

/// Each interior vertex's area plus its shares of the neighbouring boundary vertices' areas.
std::vector<double> represented_areas(const RestLaplacian& l) {
  const size_t n = l.area.size();
  std::vector<double> out(n, 0.0), weight_sum(n, 0.0);
  std::vector<int> interior_neighbours(n, 0);
  for (size_t v = 0; v < n; ++v)
    if (l.used[v] && !l.boundary[v]) out[v] = l.area[v];
  // per boundary vertex, the cotangent weights and count of its interior neighbours
  for (const auto& [ab, e] : l.edges)
    for (auto [b, u] : {ab, std::pair{ab.second, ab.first}})
      if (l.boundary[size_t(b)] && !l.boundary[size_t(u)]) {
        weight_sum[size_t(b)] += std::max(e.weight, 0.0);
        interior_neighbours[size_t(b)] += 1;
      }
  for (const auto& [ab, e] : l.edges)
    for (auto [b, u] : {ab, std::pair{ab.second, ab.first}})
      if (l.boundary[size_t(b)] && !l.boundary[size_t(u)]) {
        const double ws = weight_sum[size_t(b)];
        const double share =
            ws > 0 ? std::max(e.weight, 0.0) / ws : 1.0 / interior_neighbours[size_t(b)];
        out[size_t(u)] += share * l.area[size_t(b)];
      }
  return out;
}

}  // namespace

BendingForm build_bending_form(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                               double rigidity) {
  if (!(rigidity > 0))
    throw std::invalid_argument("hinge bending needs a bending rigidity > 0 (N m), got " +
                                std::to_string(rigidity));
  const RestLaplacian l = rest_laplacian(x0, triangles);
  const std::vector<double> represented = represented_areas(l);
  const auto n = static_cast<size_t>(x0.cols());
  // each interior vertex's Laplacian row c_v: (neighbour, weight) pairs, itself first
  std::vector<std::vector<std::pair<int, double>>> rows(n);
  for (size_t v = 0; v < n; ++v) rows[v].emplace_back(int(v), 0.0);
  for (const auto& [ab, e] : l.edges) {
    const auto [a, b] = ab;
    for (auto [p, q] : {std::pair{a, b}, std::pair{b, a}}) {
      rows[size_t(p)].emplace_back(q, e.weight);
      rows[size_t(p)][0].second -= e.weight;
    }
  }
  // Q = B sum_v (A~_v / A_v^2) c_v c_v^T over the interior vertices, and the flatness check
  std::vector<Eigen::Triplet<double>> t;
  double extent = (x0.colwise() - x0.rowwise().mean()).cwiseAbs().maxCoeff();
  for (size_t v = 0; v < n; ++v) {
    if (!l.used[v] || l.boundary[v]) continue;
    Vector3 lap = Vector3::Zero();
    for (auto [p, w] : rows[v]) lap += w * x0.col(p);
    if (lap.norm() > 1e-9 * extent * std::max(1.0, std::fabs(rows[v][0].second)))
      throw std::invalid_argument(
          "hinge bending needs a flat rest shape: the cloth is curved at particle " +
          std::to_string(v));
    const double s = rigidity * represented[v] / (l.area[v] * l.area[v]);
    for (auto [p, wp] : rows[v])
      for (auto [q, wq] : rows[v]) t.emplace_back(p, q, s * wp * wq);
  }
  BendingForm form;
  form.q.resize(Eigen::Index(n), Eigen::Index(n));
  form.q.setFromTriplets(t.begin(), t.end());
  form.q.prune(0.0);
  form.q.makeCompressed();
  return form;
}

BendingForm build_edge_bending_form(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                                    double rigidity) {
  // per interior edge (a, b) with opposite c, d: K = (cot b0 + cot b1, cot a0 + cot a1,
  // -(cot a0 + cot b0), -(cot a1 + cot b1)), E = B/2 sum |K x|^2 / (A0 + A1)
  struct Side {
    int opposite;
    double cot_a, cot_b, area;
  };
  std::map<std::pair<int, int>, std::vector<Side>> sides;
  for (const Triangle& t : triangles) {
    const double twice = (x0.col(t[1]) - x0.col(t[0])).cross(x0.col(t[2]) - x0.col(t[0])).norm();
    auto cot_at = [&](int p, int q, int r) {
      return (x0.col(q) - x0.col(p)).dot(x0.col(r) - x0.col(p)) / twice;
    };
    for (int k = 0; k < 3; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)], c = t[size_t((k + 2) % 3)];
      const int lo = std::min(a, b), hi = std::max(a, b);
      sides[{lo, hi}].push_back({c, cot_at(lo, hi, c), cot_at(hi, lo, c), 0.5 * twice});
    }
  }
  std::vector<Eigen::Triplet<double>> t;
  for (const auto& [ab, sd] : sides) {
    if (sd.size() != 2) continue;
    const int idx[4] = {ab.first, ab.second, sd[0].opposite, sd[1].opposite};
    const double k[4] = {sd[0].cot_b + sd[1].cot_b, sd[0].cot_a + sd[1].cot_a,
                         -(sd[0].cot_a + sd[0].cot_b), -(sd[1].cot_a + sd[1].cot_b)};
    const double s = rigidity / (sd[0].area + sd[1].area);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) t.emplace_back(idx[i], idx[j], s * k[i] * k[j]);
  }
  BendingForm form;
  form.q.resize(x0.cols(), x0.cols());
  form.q.setFromTriplets(t.begin(), t.end());
  form.q.makeCompressed();
  return form;
}

BendingForm renumbered(const BendingForm& form, const std::vector<int>& new_of_old) {
  if (form.empty()) return form;
  std::vector<Eigen::Triplet<double>> t;
  for (int col = 0; col < form.q.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(form.q, col); it; ++it)
      t.emplace_back(new_of_old[size_t(it.row())], new_of_old[size_t(col)], it.value());
  BendingForm out;
  out.q.resize(form.q.rows(), form.q.cols());
  out.q.setFromTriplets(t.begin(), t.end());
  out.q.makeCompressed();
  return out;
}

}  // namespace cloth
