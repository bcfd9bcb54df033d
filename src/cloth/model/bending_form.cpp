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

/// A boundary vertex's area handed to one interior neighbour (m^2).
struct Share {
  int boundary = 0, interior = 0;
  double area = 0;
};

/// Each boundary vertex's area (#P `area`) split among its interior neighbours in proportion
/// to the cotangent weights joining them (equally when those are all zero).
std::vector<Share> boundary_shares(const RestLaplacian& l, const std::vector<double>& area) {
  const size_t n = l.area.size();
  std::vector<double> weight_sum(n, 0.0);
  std::vector<int> interior_neighbours(n, 0);
  // per boundary vertex, the cotangent weights and count of its interior neighbours
  for (const auto& [ab, e] : l.edges)
    for (auto [b, u] : {ab, std::pair{ab.second, ab.first}})
      if (l.boundary[size_t(b)] && !l.boundary[size_t(u)]) {
        weight_sum[size_t(b)] += std::max(e.weight, 0.0);
        interior_neighbours[size_t(b)] += 1;
      }
  std::vector<Share> out;
  for (const auto& [ab, e] : l.edges)
    for (auto [b, u] : {ab, std::pair{ab.second, ab.first}})
      if (l.boundary[size_t(b)] && !l.boundary[size_t(u)]) {
        const double ws = weight_sum[size_t(b)];
        const double share =
            ws > 0 ? std::max(e.weight, 0.0) / ws : 1.0 / interior_neighbours[size_t(b)];
        out.push_back({b, u, share * area[size_t(b)]});
      }
  return out;
}

/// Each interior vertex's area plus its shares of the neighbouring boundary vertices' areas.
std::vector<double> represented_areas(const RestLaplacian& l) {
  std::vector<double> out(l.area.size(), 0.0);
  for (size_t v = 0; v < out.size(); ++v)
    if (l.used[v] && !l.boundary[v]) out[v] = l.area[v];
  for (const Share& s : boundary_shares(l, l.area)) out[size_t(s.interior)] += s.area;
  return out;
}

/// Each vertex's barycentric area outside the clamp: a third of each of its triangles that
/// has a particle not in `rigid` (#P, 1 held on every axis, or empty).
std::vector<double> unclamped_areas(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                                    const std::vector<char>& rigid) {
  std::vector<double> out(size_t(x0.cols()), 0.0);
  for (const Triangle& t : triangles) {
    if (!rigid.empty() && rigid[size_t(t[0])] && rigid[size_t(t[1])] && rigid[size_t(t[2])])
      continue;
    const double a = (x0.col(t[1]) - x0.col(t[0])).cross(x0.col(t[2]) - x0.col(t[0])).norm() / 6;
    for (int p : t) out[size_t(p)] += a;
  }
  return out;
}

void check_rigidity(double rigidity) {
  if (!(rigidity > 0))
    throw std::invalid_argument("hinge bending needs a bending rigidity > 0 (N m), got " +
                                std::to_string(rigidity));
}

/// An interior edge ab and the vertices c, d across it in its two triangles. For x linear on
/// each rest triangle, K . x is minus the edge's length times the jump of x's derivative
/// across the edge (along the rest normal `across`); it is zero when x is linear throughout.
struct Hinge {
  int vertex[4] = {0, 0, 0, 0};      // a, b, c, d
  double k[4] = {0, 0, 0, 0};        // (cot b0 + cot b1, cot a0 + cot a1, -(cot a0 + cot b0), ...)
  double area = 0;                   // m^2, A0 + A1 of the two triangles
  Vector3 across = Vector3::Zero();  // unit, in the rest plane, normal to the edge
};

/// The interior edges of the rest surface as hinges (edges of three or more triangles skipped).
std::vector<Hinge> hinges(const Matrix3X& x0, const std::vector<Triangle>& triangles) {
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
  std::vector<Hinge> out;
  for (const auto& [ab, sd] : sides) {
    if (sd.size() != 2) continue;
    Hinge h;
    const int idx[4] = {ab.first, ab.second, sd[0].opposite, sd[1].opposite};
    const double k[4] = {sd[0].cot_b + sd[1].cot_b, sd[0].cot_a + sd[1].cot_a,
                         -(sd[0].cot_a + sd[0].cot_b), -(sd[1].cot_a + sd[1].cot_b)};
    std::copy(idx, idx + 4, h.vertex);
    std::copy(k, k + 4, h.k);
    h.area = sd[0].area + sd[1].area;
    const Vector3 e = x0.col(ab.second) - x0.col(ab.first);
    const Vector3 c = x0.col(sd[0].opposite) - x0.col(ab.first);
    h.across = (c - c.dot(e) / e.squaredNorm() * e).normalized();
    out.push_back(h);
  }
  return out;
}

/// An orthonormal frame of the rest shape's plane.
struct RestPlane {
  Vector3 normal, u, v;
};

/// The plane of the largest triangle; throws when a particle of the surface lies off it.
RestPlane rest_plane(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                     const RestLaplacian& l) {
  RestPlane f;
  double largest = -1.0;
  Vector3 origin = Vector3::Zero();
  for (const Triangle& t : triangles) {
    const Vector3 e = x0.col(t[1]) - x0.col(t[0]);
    const Vector3 n = e.cross(x0.col(t[2]) - x0.col(t[0]));
    if (n.norm() <= largest) continue;
    largest = n.norm();
    f = {n.normalized(), e.normalized(), n.normalized().cross(e.normalized())};
    origin = x0.col(t[0]);
  }
  const double extent = (x0.colwise() - x0.rowwise().mean()).cwiseAbs().maxCoeff();
  for (Eigen::Index p = 0; p < x0.cols(); ++p)
    if (l.used[size_t(p)] && std::fabs(f.normal.dot(x0.col(p) - origin)) > 1e-9 * extent)
      throw std::invalid_argument(
          "hinge bending needs a flat rest shape: the cloth is curved at particle " +
          std::to_string(p));
  return f;
}

/// Unit outward normals in the rest plane at the boundary vertices (the mean of their two
/// boundary edges'), zero elsewhere and where those cancel.
std::vector<Vector3> boundary_normals(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                                      const RestLaplacian& l) {
  std::vector<Vector3> out(size_t(x0.cols()), Vector3::Zero());
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)], c = t[size_t((k + 2) % 3)];
      if (l.edges.at({std::min(a, b), std::max(a, b)}).triangles != 1) continue;
      const Vector3 e = (x0.col(b) - x0.col(a)).normalized();
      const Vector3 away = x0.col(a) - x0.col(c);
      const Vector3 normal = (away - away.dot(e) * e).normalized();
      out[size_t(a)] += normal;
      out[size_t(b)] += normal;
    }
  for (Vector3& n : out) n = n.norm() > 1e-6 ? Vector3(n.normalized()) : Vector3::Zero();
  return out;
}

/// One term weight (d1^T M_v d2)^2 of the energy at a vertex v, with M_v its integrated
/// Hessian sum_{e at v} (K_e x) / 2 n_e n_e^T (n_e the edge's rest normal `across`).
struct Component {
  Vector3 d1, d2;
  double weight = 0;  // N m / m^2
};

/// Adds sum_c weight_c s_c s_c^T to Q's triplets, s_c the stencil of component c of M_v
/// over the vertices of v's hinges (`at`: indices into hs of the edges ending at v).
void add_vertex_terms(const std::vector<Hinge>& hs, const std::vector<int>& at,
                      const std::vector<Component>& components,
                      std::vector<Eigen::Triplet<double>>& t) {
  std::vector<int> idx;
  for (int i : at) idx.insert(idx.end(), hs[size_t(i)].vertex, hs[size_t(i)].vertex + 4);
  std::sort(idx.begin(), idx.end());
  idx.erase(std::unique(idx.begin(), idx.end()), idx.end());
  const auto m = Eigen::Index(idx.size());
  // one stencil row per component
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(Eigen::Index(components.size()), m);
  for (size_t c = 0; c < components.size(); ++c)
    for (int i : at) {
      const Hinge& h = hs[size_t(i)];
      const double g = 0.5 * h.across.dot(components[c].d1) * h.across.dot(components[c].d2);
      for (int k = 0; k < 4; ++k) {
        const auto pos = std::lower_bound(idx.begin(), idx.end(), h.vertex[k]) - idx.begin();
        s(Eigen::Index(c), pos) += g * h.k[k];
      }
    }
  // their weighted outer products
  for (Eigen::Index p = 0; p < m; ++p)
    for (Eigen::Index q = 0; q < m; ++q) {
      double value = 0.0;
      for (size_t c = 0; c < components.size(); ++c)
        value += components[c].weight * s(Eigen::Index(c), p) * s(Eigen::Index(c), q);
      if (value != 0.0) t.emplace_back(idx[size_t(p)], idx[size_t(q)], value);
    }
}

/// The n by n form summed from triplets t, its exact zeros dropped.
BendingForm assembled_form(size_t n, const std::vector<Eigen::Triplet<double>>& t) {
  BendingForm form;
  form.q.resize(Eigen::Index(n), Eigen::Index(n));
  form.q.setFromTriplets(t.begin(), t.end());
  form.q.prune(0.0);
  form.q.makeCompressed();
  return form;
}

}  // namespace

BendingForm build_bending_form(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                               double rigidity, const std::vector<char>& rigid) {
  check_rigidity(rigidity);
  const RestLaplacian l = rest_laplacian(x0, triangles);
  const std::vector<double> area = unclamped_areas(x0, triangles, rigid);
  const RestPlane plane = rest_plane(x0, triangles, l);
  const std::vector<Hinge> hs = hinges(x0, triangles);
  const std::vector<Vector3> outward = boundary_normals(x0, triangles, l);
  const auto n = static_cast<size_t>(x0.cols());
  // the hinges at each vertex: the edges ending there
  std::vector<std::vector<int>> at(n);
  for (size_t i = 0; i < hs.size(); ++i)
    for (int k : {0, 1}) at[size_t(hs[i].vertex[k])].push_back(int(i));
  std::vector<Eigen::Triplet<double>> t;
  for (size_t v = 0; v < n; ++v) {
    if (!l.used[v] || at[v].empty() || !(area[v] > 0)) continue;
    const double w = rigidity / area[v];
    // an interior vertex: |M|^2 = M_uu^2 + M_vv^2 + 2 M_uv^2 over its area
    if (!l.boundary[v]) {
      add_vertex_terms(
          hs, at[v], {{plane.u, plane.u, w}, {plane.v, plane.v, w}, {plane.u, plane.v, 2 * w}}, t);
      continue;
    }
    // a boundary vertex: the parts along its edge, M_tt^2 + 2 M_tn^2; its M_nn is not
    // measured (the edges along the boundary have one side), so its nn part goes below
    const Vector3 tangent = plane.normal.cross(outward[v]);
    if (outward[v].norm() > 0)
      add_vertex_terms(hs, at[v], {{tangent, tangent, w}, {tangent, outward[v], 2 * w}}, t);
  }
  // each boundary vertex's nn part on its interior neighbours: their M_nn along its normal
  for (const Share& s : boundary_shares(l, area)) {
    const auto u = size_t(s.interior);
    const Vector3& nb = outward[size_t(s.boundary)];
    if (!at[u].empty() && nb.norm() > 0 && area[u] > 0)
      add_vertex_terms(hs, at[u], {{nb, nb, rigidity * s.area / (area[u] * area[u])}}, t);
  }
  return assembled_form(n, t);
}

BendingForm build_laplacian_bending_form(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                                         double rigidity) {
  check_rigidity(rigidity);
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
  return assembled_form(n, t);
}

BendingForm build_edge_bending_form(const Matrix3X& x0, const std::vector<Triangle>& triangles,
                                    double rigidity) {
  // E = B/2 sum_e |K_e x|^2 / (A0 + A1) over the interior edges
  check_rigidity(rigidity);
  std::vector<Eigen::Triplet<double>> t;
  for (const Hinge& h : hinges(x0, triangles))
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        t.emplace_back(h.vertex[i], h.vertex[j], rigidity / h.area * h.k[i] * h.k[j]);
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
