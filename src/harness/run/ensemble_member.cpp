#include "harness/run/ensemble_member.hpp"

#include <algorithm>
#include <memory>

#include "cloth/model/triangle_mesh.hpp"

namespace clothbench {

namespace {

// splitmix64: a small generator whose output is fixed by its state on every platform
struct SplitMix {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  // uniform in [-1, 1)
  double symmetric() { return double(next() >> 11) * 0x1.0p-52 - 1.0; }
  cloth::Vector3 vector() {
    const double a = symmetric(), b = symmetric(), c = symmetric();
    return {a, b, c};
  }
};

}  // namespace

cloth::Scene perturbed_scene(const cloth::Scene& scene, int member, std::uint64_t seed) {
  if (member == 0) return scene;
  cloth::Scene s = scene;
  SplitMix rng{seed * 0x100000001B3ULL + std::uint64_t(member)};
  // a few draws to leave the generator's start behind
  for (int k = 0; k < 4; ++k) rng.next();
  // the cloth moves as a whole (a flat cloth stays flat), relative to its extent
  const cloth::Vector3 offset = rng.vector();
  if (!s.mesh) {
    s.cloth.center += kRoundOffPerturbation * std::max(s.cloth.size_u, s.cloth.size_v) * offset;
    return s;
  }
  auto mesh = std::make_shared<cloth::TriangleMesh>(*s.mesh);
  const double extent = (mesh->x.rowwise().maxCoeff() - mesh->x.rowwise().minCoeff()).norm();
  mesh->x.colwise() += kRoundOffPerturbation * extent * offset;
  s.mesh = mesh;
  return s;
}

}  // namespace clothbench
