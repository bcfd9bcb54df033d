#include "cloth/model/model.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "cloth/model/triangle_mesh.hpp"

namespace cloth {

Scene seed_scene(int per_edge) {
  Scene s;
  // the seed's total mass (625 kg) spread evenly: 1 kg a particle at 25 x 25
  s.cloth.nu = s.cloth.nv = per_edge;
  s.cloth.particle_mass = 625.0 / (double(per_edge) * per_edge);
  s.spheres.push_back(Sphere{});
  s.held.assign(static_cast<size_t>(s.particle_count()), 0);
  const ClothParams& c = s.cloth;
  for (int j : {0, c.nv - 1})
    for (int i : {0, c.nu - 1}) s.held[static_cast<size_t>(particle_index(c, i, j))] = kHoldAll;
  return s;
}

Matrix3X grid_positions(const ClothParams& c) {
  Matrix3X x(3, c.nu * c.nv);
  for (int j = 0; j < c.nv; ++j) {
    for (int i = 0; i < c.nu; ++i) {
      // a grid of one particle along a direction sits at the centre
      const double u = c.nu > 1 ? (double(i) / (c.nu - 1) - 0.5) * c.size_u : 0.0;
      const double v = c.nv > 1 ? (double(j) / (c.nv - 1) - 0.5) * c.size_v : 0.0;
      Vector3 p = c.center;
      p.x() += u;
      if (c.plane == Plane::xz)
        p.z() += v;
      else
        p.y() += v;
      x.col(j * c.nu + i) = p;
    }
  }
  return x;
}

std::vector<Triangle> grid_triangles(int nu, int nv) {
  std::vector<Triangle> out;
  if (nu < 2 || nv < 2) return out;
  out.reserve(2 * static_cast<size_t>(nu - 1) * static_cast<size_t>(nv - 1));
  for (int j = 0; j + 1 < nv; ++j)
    for (int i = 0; i + 1 < nu; ++i) {
      const int p00 = j * nu + i, p10 = p00 + 1, p01 = p00 + nu, p11 = p01 + 1;
      out.push_back({p00, p10, p11});
      out.push_back({p00, p11, p01});
    }
  return out;
}

const char* bend_model_name(BendModel model) {
  return model == BendModel::hinge ? "hinge" : "springs";
}

int Scene::particle_count() const {
  return mesh ? static_cast<int>(mesh->x.cols()) : cloth.nu * cloth.nv;
}

Matrix3X rest_positions(const Scene& scene) {
  return scene.mesh ? scene.mesh->x : grid_positions(scene.cloth);
}

namespace {

// a grid's particles weigh alike; a mesh's vertices a third of their triangles' area each
VectorX particle_masses(const Scene& scene) {
  const ClothParams& c = scene.cloth;
  const int n = scene.particle_count();
  if (scene.mesh) {
    const double area = mesh_area(*scene.mesh);
    const double density = c.areal_density > 0            ? c.areal_density
                           : c.total_mass > 0 && area > 0 ? c.total_mass / area
                                                          : 0.0;
    if (!(density > 0)) throw std::invalid_argument("a mesh needs areal_density or total_mass");
    return lumped_masses(*scene.mesh, density);
  }
  const double total = c.areal_density > 0 ? c.areal_density * c.size_u * c.size_v : c.total_mass;
  const double pm = total > 0 ? total / n : c.particle_mass;
  if (!(pm > 0)) throw std::invalid_argument("particle mass must be positive");
  return VectorX::Constant(n, pm);
}

// one structural spring per edge, one bend spring per interior edge across its two triangles
// (a grid lattice: structural along its yarns, shear on its squares' diagonals, bend two sides
// apart along a yarn), in the order the general kernel runs fastest
SpringSet mesh_springs(const ClothParams& c, const TriangleMesh& mesh) {
  const MeshEdges e = mesh_edges(mesh);
  SpringSet set;
  set.damping = c.damping;
  const auto add = [&](int a, int b, double k, SpringKind kind) {
    set.list.push_back(
        {std::min(a, b), std::max(a, b), (mesh.x.col(b) - mesh.x.col(a)).norm(), k, kind});
  };
  // a grid lattice's springs follow its yarns and squares, a grid's sets; else its edges
  const LatticeLinks lat = lattice_links(mesh);
  const bool lattice = !mesh.cells.empty();
  if (c.k_structural > 0)
    for (const auto& [a, b] : lattice ? lat.structural : e.edges)
      add(a, b, c.k_structural, SpringKind::structural);
  if (c.k_shear > 0)
    for (const auto& [a, b] : lat.shear) add(a, b, c.k_shear, SpringKind::shear);
  if (c.k_bend > 0)
    for (const auto& [a, b] : lattice ? lat.bend : e.bend_pairs)
      add(a, b, c.k_bend, SpringKind::bend);
  // laid out for the general kernel (each particle's first springs together, so most blocks
  // start at consecutive particles), the particles keeping their numbers
  std::vector<int> same(static_cast<size_t>(mesh.vertex_count()));
  for (size_t p = 0; p < same.size(); ++p) same[p] = static_cast<int>(p);
  return renumbered(set, same);
}

// the particles, their masses and held axes of a grid or a mesh
void build_particles(const Scene& scene, Model& m) {
  const ClothParams& c = scene.cloth;
  if (!scene.mesh && (c.nu < 1 || c.nv < 1 || c.nu * c.nv < 2))
    throw std::invalid_argument("the cloth needs at least 1 x 2 particles, got " +
                                std::to_string(c.nu) + " x " + std::to_string(c.nv));
  const int n = scene.particle_count();
  // a mesh is listed as one row of vertices in file order: i is the vertex index, j is 0
  m.nu = scene.mesh ? n : c.nu;
  m.nv = scene.mesh ? 1 : c.nv;
  m.is_mesh = scene.mesh != nullptr;
  m.x0 = rest_positions(scene);
  m.mass = particle_masses(scene);
  m.free = Matrix3X::Ones(3, n);
  m.inv_mass = VectorX::Zero(n);
  for (int p = 0; p < n; ++p) {
    if (m.mass[p] > 0) {
      m.inv_mass[p] = 1.0 / m.mass[p];
      continue;
    }
    // a vertex of no triangle has no area and no mass: it stays where it is
    m.free.col(p).setZero();
    m.any_held = true;
  }
}

}  // namespace

Model build_model(const Scene& scene) {
  const ClothParams& c = scene.cloth;
  const int n = scene.particle_count();
  Model m;
  build_particles(scene, m);
  if (!scene.held.empty()) {
    if (static_cast<int>(scene.held.size()) != n)
      throw std::invalid_argument("held-axis mask has " + std::to_string(scene.held.size()) +
                                  " entries for " + std::to_string(n) + " particles");
    for (int p = 0; p < n; ++p)
      for (int a = 0; a < 3; ++a)
        if (scene.held[static_cast<size_t>(p)] & (1u << a)) {
          m.free(a, p) = 0.0;
          m.any_held = true;
        }
  }
  for (const Handle& h : scene.handles)
    for (int p : h.particles) {
      if (p < 0 || p >= n)
        throw std::invalid_argument("handle particle " + std::to_string(p) + " is not one of " +
                                    std::to_string(n));
      m.free.col(p).setZero();
      m.any_held = true;
    }
  // the hinge model replaces the bend springs with its quadratic form over the triangles
  ClothParams springs = c;
  if (c.bend_model == BendModel::hinge) springs.k_bend = 0.0;
  m.springs = scene.mesh ? mesh_springs(springs, *scene.mesh) : build_springs(springs, m.x0);
  m.triangles = scene.mesh ? scene.mesh->triangles : grid_triangles(c.nu, c.nv);
  // particles held on every axis are the hinge's rigid clamp
  if (c.bend_model == BendModel::hinge) {
    std::vector<char> rigid(size_t(n), 0);
    for (Eigen::Index p = 0; p < n; ++p) rigid[size_t(p)] = m.free.col(p).isZero() ? 1 : 0;
    m.springs.bending = build_bending_form(m.x0, m.triangles, c.bending_rigidity, rigid);
  }
  m.gravity = scene.gravity;
  m.air_drag = c.air_drag;
  m.self_collision = c.self_collision;
  m.thickness = c.thickness;
  m.self_friction = c.self_friction;
  m.wind = scene.wind;
  m.spheres = scene.spheres;
  m.shapes = scene.shapes;
  for (HalfSpace& h : m.shapes.planes) {
    if (!(h.normal.norm() > 0)) throw std::invalid_argument("a plane's normal must not be zero");
    h.normal.normalize();
  }
  m.handles = scene.handles;
  return m;
}

}  // namespace cloth
