#include "harness/scenario/scenario.hpp"

#include <stdexcept>

#include "cloth/model/model.hpp"

namespace clothbench {

int Scenario::reference_index() const {
  if (engines.empty()) throw std::invalid_argument("scenario \"" + name + "\" has no engine");
  if (reference.empty()) return 0;
  for (size_t e = 0; e < engines.size(); ++e)
    if (engines[e].name == reference) return static_cast<int>(e);
  throw std::invalid_argument("reference engine \"" + reference + "\" is not an engine of \"" +
                              name + "\"");
}

std::vector<std::uint8_t> held_mask(const cloth::ClothParams& cloth,
                                    const std::vector<ConstraintSpec>& constraints) {
  const int nu = cloth.nu, nv = cloth.nv;
  std::vector<std::uint8_t> mask(static_cast<size_t>(nu * nv), 0);
  const auto hold = [&](int i, int j, std::uint8_t axes) {
    mask[static_cast<size_t>(cloth::particle_index(cloth, i, j))] |= axes;
  };
  for (const ConstraintSpec& c : constraints) {
    const std::string& s = c.select;
    if (s == "corners") {
      for (int j : {0, nv - 1})
        for (int i : {0, nu - 1}) hold(i, j, c.hold);
    } else if (s == "edge:u0" || s == "edge:u1") {
      const int i = s == "edge:u0" ? 0 : nu - 1;
      for (int j = 0; j < nv; ++j) hold(i, j, c.hold);
    } else if (s == "edge:v0" || s == "edge:v1") {
      const int j = s == "edge:v0" ? 0 : nv - 1;
      for (int i = 0; i < nu; ++i) hold(i, j, c.hold);
    } else if (s == "disk") {
      // the disk lies in the cloth plane's two world axes: (x, z) or (x, y)
      const cloth::Matrix3X x = cloth::grid_positions(cloth);
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
          throw std::invalid_argument("grid index (" + std::to_string(i) + ", " +
                                      std::to_string(j) + ") is outside the " + std::to_string(nu) +
                                      " x " + std::to_string(nv) + " grid");
        hold(i, j, c.hold);
      }
    } else {
      throw std::invalid_argument("unknown constraint selection \"" + s + "\"");
    }
  }
  return mask;
}

}  // namespace clothbench
