#include "harness/scenario/scenario.hpp"

#include <stdexcept>

#include "cloth/model/model.hpp"
#include "cloth/model/triangle_mesh.hpp"

namespace clothbench {

int Scenario::reference_index() const {
  if (engines.empty()) throw std::invalid_argument("scenario \"" + name + "\" has no engine");
  if (reference.empty()) return 0;
  for (size_t e = 0; e < engines.size(); ++e)
    if (engines[e].name == reference) return static_cast<int>(e);
  throw std::invalid_argument("reference engine \"" + reference + "\" is not an engine of \"" +
                              name + "\"");
}

const cloth::Scene& engine_scene(const Scenario& s, const EngineSpec& e) {
  return e.scene ? *e.scene : s.scene;
}

namespace {

// the grid's own selections: corners, edges, a disk in the cloth plane, (i, j) indices
void hold_on_grid(const cloth::ClothParams& cloth, const cloth::Matrix3X& x,
                  const ConstraintSpec& c, std::vector<std::uint8_t>& mask) {
  const int nu = cloth.nu, nv = cloth.nv;
  const auto hold = [&](int i, int j) {
    mask[static_cast<size_t>(cloth::particle_index(cloth, i, j))] |= c.hold;
  };
  const std::string& s = c.select;
  if (s == "corners") {
    for (int j : {0, nv - 1})
      for (int i : {0, nu - 1}) hold(i, j);
  } else if (s == "edge:u0" || s == "edge:u1") {
    const int i = s == "edge:u0" ? 0 : nu - 1;
    for (int j = 0; j < nv; ++j) hold(i, j);
  } else if (s == "edge:v0" || s == "edge:v1") {
    const int j = s == "edge:v0" ? 0 : nv - 1;
    for (int i = 0; i < nu; ++i) hold(i, j);
  } else if (s == "disk") {
    // the disk lies in the cloth plane's two world axes: (x, z) or (x, y)
    const int second = cloth.plane == cloth::Plane::xz ? 2 : 1;
    // inclusive, with room for round-off in the grid positions
    const double r2 = c.disk_radius * c.disk_radius * (1.0 + 1e-12);
    for (int p = 0; p < nu * nv; ++p) {
      const double da = x(0, p) - c.disk_center_x, db = x(second, p) - c.disk_center_z;
      if (da * da + db * db <= r2) mask[static_cast<size_t>(p)] |= c.hold;
    }
  } else if (s == "indices") {
    for (const auto& [i, j] : c.indices) {
      if (i < 0 || i >= nu || j < 0 || j >= nv)
        throw std::invalid_argument("grid index (" + std::to_string(i) + ", " + std::to_string(j) +
                                    ") is outside the " + std::to_string(nu) + " x " +
                                    std::to_string(nv) + " grid");
      hold(i, j);
    }
  } else {
    throw std::invalid_argument("selection \"" + s + "\" is not one of a grid's");
  }
}

// a mesh's own selections: a named group, vertex indices
void hold_on_mesh(const cloth::TriangleMesh& mesh, const ConstraintSpec& c,
                  std::vector<std::uint8_t>& mask) {
  if (c.select == "group") {
    for (const auto& [name, vertices] : mesh.groups)
      if (name == c.group) {
        for (int p : vertices) mask[static_cast<size_t>(p)] |= c.hold;
        return;
      }
    throw std::invalid_argument("the mesh has no group \"" + c.group + "\"");
  }
  if (c.select == "indices") {
    for (int p : c.vertices) {
      if (p < 0 || p >= static_cast<int>(mask.size()))
        throw std::invalid_argument("vertex index " + std::to_string(p) +
                                    " is outside the mesh's " + std::to_string(mask.size()) +
                                    " vertices");
      mask[static_cast<size_t>(p)] |= c.hold;
    }
    return;
  }
  throw std::invalid_argument("selection \"" + c.select + "\" is not one of a mesh's");
}

// the selections of any cloth: a ball or a box around rest positions
bool hold_in_space(const cloth::Matrix3X& x, const ConstraintSpec& c,
                   std::vector<std::uint8_t>& mask) {
  if (c.select != "within" && c.select != "box") return false;
  // inclusive, with room for round-off in the rest positions
  const double r2 = c.disk_radius * c.disk_radius * (1.0 + 1e-12);
  for (Eigen::Index p = 0; p < x.cols(); ++p) {
    const cloth::Vector3 q = x.col(p);
    const bool in = c.select == "within" ? (q - c.center).squaredNorm() <= r2
                                         : (q.array() >= c.box_min.array()).all() &&
                                               (q.array() <= c.box_max.array()).all();
    if (in) mask[static_cast<size_t>(p)] |= c.hold;
  }
  return true;
}

}  // namespace

std::vector<std::uint8_t> held_mask(const cloth::Scene& scene,
                                    const std::vector<ConstraintSpec>& constraints) {
  std::vector<std::uint8_t> mask(static_cast<size_t>(scene.particle_count()), 0);
  const cloth::Matrix3X x = cloth::rest_positions(scene);
  for (const ConstraintSpec& c : constraints) {
    if (hold_in_space(x, c, mask)) continue;
    if (scene.mesh)
      hold_on_mesh(*scene.mesh, c, mask);
    else
      hold_on_grid(scene.cloth, x, c, mask);
  }
  return mask;
}

}  // namespace clothbench
