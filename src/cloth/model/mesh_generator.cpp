#include "cloth/model/mesh_generator.hpp"

// compiled with -ffp-contract=off (src/cloth/CMakeLists.txt): see the header on determinism

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "cloth/model/mesh_check.hpp"

namespace cloth {

namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;
/// Jitter of interior points, as a fraction of the local spacing in each direction: small
/// enough that no point leaves its cell, so none crosses the boundary or another ring.
constexpr double kJitter = 0.15;

/// splitmix64 (Steele, Lea and Flood 2014): the one source of randomness.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1): the top 53 bits times 2^-53.
  double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Uniform in [-a, a).
  double jitter(double a) { return a * (2.0 * unit() - 1.0); }
};

/// cos and sin of the angle 2 pi turns, from Taylor polynomials (Horner's scheme, to x^15 and
/// x^14; truncation below 1e-16) on [-pi/4, pi/4] after a reduction by whole and quarter
/// turns: plain IEEE arithmetic, the same bits on every machine.
void cos_sin_turns(double turns, double& c, double& s) {
  const double t = turns - std::floor(turns);
  const double q = std::floor(4.0 * t + 0.5);
  const double x = (t - 0.25 * q) * kTwoPi;
  const double x2 = x * x;
  double sx = 1.0, cx = 1.0;
  for (int k = 7; k >= 1; --k) {
    sx = 1.0 - x2 / ((2 * k) * (2 * k + 1)) * sx;
    cx = 1.0 - x2 / ((2 * k - 1) * (2 * k)) * cx;
  }
  sx *= x;
  switch (static_cast<int>(q) & 3) {
    case 0:
      c = cx, s = sx;
      break;
    case 1:
      c = -sx, s = cx;
      break;
    case 2:
      c = -cx, s = -sx;
      break;
    default:
      c = sx, s = -cx;
      break;
  }
}

/// A planar point set (u, v) with, per point, a mark: 1 on the annulus' inner ring.
struct Points {
  std::vector<double> u, v;
  std::vector<char> inner;
  void add(double pu, double pv, bool on_inner = false) {
    u.push_back(pu);
    v.push_back(pv);
    inner.push_back(on_inner ? 1 : 0);
  }
  int size() const { return static_cast<int>(u.size()); }
};

int count_of(double length, double spacing, int at_least) {
  return std::max(at_least, static_cast<int>(std::lround(length / spacing)));
}

/// Rings of radius r0 < ... < r1 (r0 = 0: a centre point instead of a ring), each rotated by a
/// random phase; the first (when r0 > 0) and last ring exact, the rest jittered.
Points rings(double r0, double r1, double h, SplitMix64& rng) {
  Points p;
  const int m = count_of(r1 - r0, h, 1);
  const double dr = (r1 - r0) / m;
  for (int k = 0; k <= m; ++k) {
    const double r = k == m ? r1 : r0 + k * dr;
    if (r == 0.0) {
      p.add(rng.jitter(kJitter * dr), rng.jitter(kJitter * dr));
      continue;
    }
    const bool exact = k == 0 || k == m;
    const int n = count_of(kTwoPi * r, h, 3);
    const double phase = rng.unit();
    for (int i = 0; i < n; ++i) {
      double turns = (i + phase) / n, radius = r;
      if (!exact) {
        turns += rng.jitter(kJitter / n);
        radius += rng.jitter(kJitter * dr);
      }
      double c, s;
      cos_sin_turns(turns, c, s);
      p.add(radius * c, radius * s, exact && k == 0);
    }
  }
  return p;
}

/// A triangular lattice on [-su/2, su/2] x [-sv/2, sv/2] (periodic in u: no points at
/// u = su/2, no exact column at u = -su/2), rows at exact v; interior points jittered.
Points lattice(double su, double sv, double h, bool periodic, SplitMix64& rng) {
  Points p;
  const int nu = count_of(su, h, 1);
  const int nv = count_of(sv, h * std::sqrt(3.0) / 2, 1);
  const double du = su / nu, dv = sv / nv;
  for (int j = 0; j <= nv; ++j) {
    const double v = j == nv ? sv / 2 : -sv / 2 + j * dv;
    const bool edge_row = j == 0 || j == nv;
    const double shift = j % 2 ? 0.5 : 0.0;
    // the row's points: the two sides exact (unless periodic), the rest shifted on odd rows
    std::vector<double> us;
    if (!periodic && shift != 0.0) us.push_back(-su / 2);
    for (int i = 0; i < nu + (periodic || shift != 0.0 ? 0 : 1); ++i)
      us.push_back(!periodic && shift == 0.0 && i == nu ? su / 2 : -su / 2 + (i + shift) * du);
    if (!periodic && shift != 0.0) us.push_back(su / 2);
    for (std::size_t i = 0; i < us.size(); ++i) {
      const bool side = !periodic && (i == 0 || i + 1 == us.size());
      if (edge_row || side) {
        p.add(us[i], v);
      } else {
        p.add(us[i] + rng.jitter(kJitter * du), v + rng.jitter(kJitter * dv));
      }
    }
  }
  return p;
}

/// The Delaunay triangles of the planar points (indices into p), each counter-clockwise,
/// from Qhull's lower hull of the points lifted onto a paraboloid. Triangles of zero area
/// (Qhull's split of a cocircular facet, only ever inside the annulus' empty hole) are left out.
std::vector<std::array<int, 3>> delaunay(const std::vector<double>& u,
                                         const std::vector<double>& v) {
  const int n = static_cast<int>(u.size());
  std::vector<coordT> points(2 * u.size());
  for (int i = 0; i < n; ++i) points[2 * i] = u[i], points[2 * i + 1] = v[i];
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, stderr);
  char options[] = "qhull d Qt Qbb Qc Qz";
  const int exitcode = qh_new_qhull(qh, 2, n, points.data(), False, options, nullptr, stderr);

  // the lower hull's triangles, turned counter-clockwise
  std::vector<std::array<int, 3>> out;
  if (exitcode == 0) {
    facetT* facet;
    vertexT *vertex, **vertexp;
    FORALLfacets {
      if (facet->upperdelaunay) continue;
      std::array<int, 3> t{};
      int k = 0;
      FOREACHvertex_(facet->vertices) {
        if (k < 3) t[k] = qh_pointid(qh, vertex->point);
        ++k;
      }
      if (k != 3) continue;
      const double area2 =
          (u[t[1]] - u[t[0]]) * (v[t[2]] - v[t[0]]) - (v[t[1]] - v[t[0]]) * (u[t[2]] - u[t[0]]);
      if (area2 == 0.0) continue;
      if (area2 < 0.0) std::swap(t[1], t[2]);
      out.push_back(t);
    }
  }
  int curlong = 0, totlong = 0;
  qh_freeqhull(qh, !qh_ALL);
  qh_memfreeshort(qh, &curlong, &totlong);
  if (exitcode != 0)
    throw std::runtime_error("Qhull failed to triangulate (exit code " + std::to_string(exitcode) +
                             ")");
  return out;
}

/// Each triangle rotated to start at its smallest index (keeping its orientation), then all
/// sorted: an order independent of the one Qhull returns.
void canonical_order(std::vector<std::array<int, 3>>& tris) {
  for (auto& t : tris) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(tris.begin(), tris.end());
}

/// A flat shape: its points triangulated, the annulus' hole (triangles of three inner-ring
/// points) removed, turned to face +y (xz) or +z (xy) and placed at the centre.
TriangleMesh planar_mesh(const Points& p, const ShapeSpec& spec) {
  std::vector<std::array<int, 3>> tris;
  for (auto t : delaunay(p.u, p.v)) {
    if (p.inner[t[0]] && p.inner[t[1]] && p.inner[t[2]]) continue;
    // counter-clockwise in (u, v) faces u x v: -y in the xz plane (u along x, v along z)
    if (spec.plane == Plane::xz) std::swap(t[1], t[2]);
    tris.push_back(t);
  }
  canonical_order(tris);
  TriangleMesh mesh;
  mesh.x.resize(3, p.size());
  for (int i = 0; i < p.size(); ++i) {
    const Vector3 offset =
        spec.plane == Plane::xz ? Vector3(p.u[i], 0.0, p.v[i]) : Vector3(p.u[i], p.v[i], 0.0);
    mesh.x.col(i) = spec.center + offset;
  }
  mesh.triangles = std::move(tris);
  return mesh;
}

/// A tube: a periodic lattice in the unrolled plane (arc s in [0, C), y), triangulated with
/// copies of the points near the seam on both sides (shifted by -C and +C) so the Delaunay
/// triangles across the seam are found; of each triangle and its shifted twin the one with
/// copies on the +C side only is kept, mapped back to the original points.
TriangleMesh tube_mesh(const ShapeSpec& spec, SplitMix64& rng) {
  const double r = spec.radius, len = spec.length, h = spec.edge_length;
  const double circ = kTwoPi * r;
  Points p = lattice(circ, len, h, true, rng);
  const int n = p.size();
  // arc from 0, wrapped into [0, C) after the jitter
  for (double& s : p.u) {
    s += circ / 2;
    if (s < 0.0) s += circ;
    if (s >= circ) s -= circ;
  }
  // the extended set: originals, then copies within w of the seam, with their shifts
  const double w = std::min(circ, 4.0 * h);
  std::vector<double> eu = p.u, ev = p.v;
  std::vector<int> source(n), shift(n, 0);
  for (int i = 0; i < n; ++i) source[i] = i;
  for (int i = 0; i < n; ++i) {
    for (int sh : {-1, 1}) {
      if ((sh == 1 && p.u[i] < w) || (sh == -1 && p.u[i] >= circ - w)) {
        eu.push_back(p.u[i] + sh * circ), ev.push_back(p.v[i]);
        source.push_back(i), shift.push_back(sh);
      }
    }
  }
  std::vector<std::array<int, 3>> tris;
  for (const auto& t : delaunay(eu, ev)) {
    const int lo = std::min({shift[t[0]], shift[t[1]], shift[t[2]]});
    const int hi = std::max({shift[t[0]], shift[t[1]], shift[t[2]]});
    if (lo != 0 || hi > 1) continue;
    // counter-clockwise in (s, y) faces inward (ds x dy points to the axis): turn it
    tris.push_back({source[t[0]], source[t[2]], source[t[1]]});
  }
  canonical_order(tris);
  TriangleMesh mesh;
  mesh.x.resize(3, n);
  for (int i = 0; i < n; ++i) {
    double c, s;
    cos_sin_turns(p.u[i] / circ, c, s);
    mesh.x.col(i) = spec.center + Vector3(r * c, p.v[i], r * s);
  }
  mesh.triangles = std::move(tris);
  return mesh;
}

/// The vertex numbers of a (nu + 1) by (nv + 1) index grid, row by row from j = 0; a node
/// (i, j) with i + j odd is left out when diagonal (the 45-degree lattice's nodes), -1 there.
std::vector<int> node_numbers(int nu, int nv, bool diagonal) {
  std::vector<int> number(size_t((nu + 1) * (nv + 1)), -1);
  int next = 0;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i)
      if (!diagonal || (i + j) % 2 == 0) number[size_t(j * (nu + 1) + i)] = next++;
  return number;
}

/// A square lattice on the rectangle (MeshLattice::grid): at 0 or 90 degrees squares of the
/// index grid (i, j), split along (i, j)-(i + 1, j + 1); at 45 or 135 degrees diamonds around
/// every (i, j) with i + j odd (corners E, N, W, S at one index step), split along W-E (along
/// u), those around a boundary index cut in half by the edge.
TriangleMesh grid_lattice_mesh(const ShapeSpec& spec) {
  const double su = spec.size_u, sv = spec.size_v, h = spec.edge_length;
  const bool diagonal = std::lround(spec.lattice_angle / 45.0) % 2 != 0;
  // index steps: a side h, or at 45 degrees half a diagonal h / sqrt(2), in even numbers
  const double step = diagonal ? h / std::sqrt(2.0) : h;
  const int k = diagonal ? 2 : 1;
  const int nu = k * count_of(su, k * step, 1), nv = k * count_of(sv, k * step, 1);
  const std::vector<int> number = node_numbers(nu, nv, diagonal);
  const auto id = [&](int i, int j) {
    return i < 0 || j < 0 || i > nu || j > nv ? -1 : number[size_t(j * (nu + 1) + i)];
  };
  TriangleMesh mesh;
  std::vector<std::array<int, 3>> tris;
  const auto add = [&](int a, int b, int c) {
    // counter-clockwise in (u, v) faces u x v: -y in the xz plane (u along x, v along z)
    if (spec.plane == Plane::xz) std::swap(b, c);
    tris.push_back({a, b, c});
  };
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      if (!diagonal && i < nu && j < nv) {
        mesh.cells.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        add(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        add(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      }
      if (!diagonal || (i + j) % 2 == 0) continue;
      // a diamond's corners, counter-clockwise; one of them off the rectangle on its edge
      const int e = id(i + 1, j), n = id(i, j + 1), w = id(i - 1, j), s = id(i, j - 1);
      mesh.cells.push_back({e, n, w, s});
      if (w >= 0 && e >= 0) {
        if (s >= 0) add(w, s, e);
        if (n >= 0) add(w, e, n);
      } else {
        if (w < 0) add(s, e, n);
        if (e < 0) add(w, s, n);
      }
    }
  canonical_order(tris);
  mesh.triangles = std::move(tris);
  // positions: the last index of each axis exactly on the far edge
  mesh.x.resize(3, number.empty() ? 0 : *std::max_element(number.begin(), number.end()) + 1);
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      if (id(i, j) < 0) continue;
      const double u = i == nu ? su / 2 : -su / 2 + i * (su / nu);
      const double v = j == nv ? sv / 2 : -sv / 2 + j * (sv / nv);
      const Vector3 offset = spec.plane == Plane::xz ? Vector3(u, 0.0, v) : Vector3(u, v, 0.0);
      mesh.x.col(id(i, j)) = spec.center + offset;
    }
  return mesh;
}

bool positive(double x) {
  return std::isfinite(x) && x > 0.0;
}

}  // namespace

const char* mesh_shape_name(MeshShape shape) {
  switch (shape) {
    case MeshShape::disk:
      return "disk";
    case MeshShape::annulus:
      return "annulus";
    case MeshShape::rectangle:
      return "rectangle";
    case MeshShape::tube:
      return "tube";
  }
  return "?";
}

const char* mesh_lattice_name(MeshLattice lattice) {
  return lattice == MeshLattice::grid ? "grid" : "triangular";
}

const std::vector<MeshShape>& all_mesh_shapes() {
  static const std::vector<MeshShape> shapes = {MeshShape::disk, MeshShape::annulus,
                                                MeshShape::rectangle, MeshShape::tube};
  return shapes;
}

std::string shape_spec_problem(const ShapeSpec& spec) {
  const bool round = spec.shape != MeshShape::rectangle;
  if (!positive(spec.edge_length)) return "edge_length: expected a number > 0";
  if (!spec.center.allFinite()) return "center: expected finite numbers";
  if (round && !positive(spec.radius)) return "radius: expected a number > 0";
  if (spec.shape == MeshShape::annulus &&
      !(positive(spec.inner_radius) && spec.inner_radius < spec.radius))
    return "inner_radius: expected a number > 0 and below radius";
  // a ring narrower than an edge would let the outer polygon's chords cut into the hole
  if (spec.shape == MeshShape::annulus && spec.radius - spec.inner_radius < spec.edge_length)
    return "edge_length: at most radius - inner_radius (the ring at least one edge wide)";
  if (spec.shape == MeshShape::rectangle && !(positive(spec.size_u) && positive(spec.size_v)))
    return "size: expected two numbers > 0";
  if (spec.lattice == MeshLattice::grid && spec.shape != MeshShape::rectangle)
    return "lattice: \"grid\" applies to a rectangle alone";
  // edges along yarns or along the squares' diagonals: resolved by the lattice's own nodes
  const double eighths = spec.lattice_angle / 45.0;
  if (!std::isfinite(spec.lattice_angle) || std::abs(eighths - std::round(eighths)) > 1e-12)
    return "lattice_angle: expected a multiple of 45 degrees (the rectangle's edges then run "
           "along the yarns or along the squares' diagonals)";
  if (spec.lattice != MeshLattice::grid && spec.lattice_angle != 0.0)
    return "lattice_angle: applies to lattice = \"grid\" alone";
  if (spec.shape == MeshShape::tube && !positive(spec.length))
    return "length: expected a number > 0";
  // coarser than six edges around a round rim or one across a rectangle, the mesh is not the
  // shape (a 0.15 m disk at edge_length 10 m: four vertices, yet a drape test's verdict)
  if (round && kTwoPi * spec.radius < 6.0 * spec.edge_length)
    return std::string("edge_length: a ") + mesh_shape_name(spec.shape) +
           " needs at least six edges around (edge_length <= 2 pi radius / 6)";
  if (spec.shape == MeshShape::rectangle && spec.edge_length > std::min(spec.size_u, spec.size_v))
    return "edge_length: at most the rectangle's shorter side (at least one edge across it)";
  // the area over the area per point of a triangular lattice, h^2 sqrt(3) / 2 (a grid's h^2)
  double area = spec.size_u * spec.size_v;
  if (spec.shape == MeshShape::disk) area = kTwoPi / 2 * spec.radius * spec.radius;
  if (spec.shape == MeshShape::annulus)
    area = kTwoPi / 2 * (spec.radius * spec.radius - spec.inner_radius * spec.inner_radius);
  if (spec.shape == MeshShape::tube) area = kTwoPi * spec.radius * spec.length;
  const double h = spec.edge_length;
  const double per_point = spec.lattice == MeshLattice::grid ? h * h : h * h * std::sqrt(3.0) / 2;
  if (area / per_point > kMaxGeneratedVertices)
    return "edge_length: too small, the mesh would have more than " +
           std::to_string(kMaxGeneratedVertices) + " vertices";
  return "";
}

TriangleMesh generate_mesh(const ShapeSpec& spec) {
  const std::string problem = shape_spec_problem(spec);
  if (!problem.empty()) throw std::invalid_argument("generate_mesh: " + problem);
  SplitMix64 rng{spec.seed};
  TriangleMesh mesh;
  const double h = spec.edge_length;
  switch (spec.shape) {
    case MeshShape::disk:
      mesh = planar_mesh(rings(0.0, spec.radius, h, rng), spec);
      break;
    case MeshShape::annulus:
      mesh = planar_mesh(rings(spec.inner_radius, spec.radius, h, rng), spec);
      break;
    case MeshShape::rectangle:
      mesh = spec.lattice == MeshLattice::grid
                 ? grid_lattice_mesh(spec)
                 : planar_mesh(lattice(spec.size_u, spec.size_v, h, false, rng), spec);
      break;
    case MeshShape::tube:
      mesh = tube_mesh(spec, rng);
      break;
  }
  // a mesh of ours that check_mesh refuses is a bug here, not the user's
  const std::vector<MeshProblem> problems = check_mesh(mesh);
  if (!problems.empty())
    throw std::logic_error("generate_mesh made a bad mesh: " + problems.front().message);
  return mesh;
}

}  // namespace cloth
