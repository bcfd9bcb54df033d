#include "reference/mujoco/mujoco_refusal.hpp"

#include <cstdio>
#include <string>

#include "cloth/model/model.hpp"
#include "format/number_format.hpp"
#include "reference/mujoco/mujoco_memory.hpp"

namespace clothbench::reference {

namespace {

/// Restitution or a zero margin of one collider (key "sphere.0", ...), or nullopt.
std::optional<Refusal> collider_refusal(const cloth::Collider& c, const std::string& key,
                                        const MujocoOptions& options) {
  if (c.restitution != 0.0)
    return Refusal{"mujoco: " + key + " has restitution " + cloth::toml_double(c.restitution) +
                       ", but MuJoCo's soft contacts have no restitution coefficient; expected 0",
                   {key + ".restitution"},
                   {}};
  if (!(options.margin.value_or(c.margin) > 0.0))
    return Refusal{"mujoco: " + key + " needs a positive contact margin (the particles are " +
                       "spheres of half the margin), got " + cloth::toml_double(c.margin) + " m",
                   {key + ".margin"},
                   {"margin"}};
  return std::nullopt;
}

/// The first collider refusal of the shapes in list (keys kind.0, kind.1, ...).
template <class Shape>
std::optional<Refusal> first_refusal(const std::vector<Shape>& list, const char* kind,
                                     const MujocoOptions& options) {
  for (size_t i = 0; i < list.size(); ++i)
    if (auto r = collider_refusal(list[i], std::string(kind) + "." + std::to_string(i), options))
      return r;
  return std::nullopt;
}

/// "1.23 GB".
std::string gigabytes(double bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f GB", bytes / 1e9);
  return buf;
}

/// Why a model of these sizes does not fit: its dense arrays, named with their sizes.
std::string memory_reason(const MujocoSize& size, const MujocoOptions& options) {
  const std::string dofs = std::to_string(size.dofs), rows = std::to_string(size.rows);
  std::string why = "mujoco: this cloth needs about " + gigabytes(size.total_bytes()) +
                    " in MuJoCo 2.2.2, more than the engine's limit of " +
                    gigabytes(kMujocoMemoryLimit) + ": MuJoCo 2.2 stores the tendon Jacobian " +
                    "densely (" + std::to_string(size.tendons) + " springs by " + dofs +
                    " degrees of freedom)";
  if (size.rows > 0)
    why += ", the colliders' constraint Jacobian (" + rows + " rows by " + dofs + ") and its " +
           rows + " by " + rows + " matrix";
  const bool implicit = options.integrator == MujocoIntegrator::implicit;
  if (implicit)
    why += ", and its implicit integrator factors a dense " + dofs + " by " + dofs + " matrix";
  return why + "; use fewer particles" + (implicit ? " or integrator = \"euler\"" : "");
}

}  // namespace

std::optional<Refusal> mujoco_refusal(const MujocoOptions& options, const cloth::Scene& scene) {
  if (scene.cloth.self_collision)
    return Refusal{
        "mujoco: cannot keep a cloth's layers apart (its particle-particle contacts "
        "are excluded); set self_collision = false",
        {"cloth.self_collision"},
        {"self_collision"}};
  const cloth::Shapes& s = scene.shapes;
  for (auto r :
       {first_refusal(scene.spheres, "sphere", options), first_refusal(s.planes, "plane", options),
        first_refusal(s.boxes, "box", options), first_refusal(s.capsules, "capsule", options),
        first_refusal(s.cylinders, "cylinder", options)})
    if (r) return r;
  // MuJoCo 2.2's dense tendon and constraint arrays grow with the square of the cloth
  const MujocoSize size = mujoco_size(cloth::build_model(scene), options);
  if (size.total_bytes() > kMujocoMemoryLimit)
    return Refusal{memory_reason(size, options),
                   {"cloth.particles"},
                   options.integrator == MujocoIntegrator::implicit
                       ? std::vector<std::string>{"integrator"}
                       : std::vector<std::string>{}};
  return std::nullopt;
}

}  // namespace clothbench::reference
