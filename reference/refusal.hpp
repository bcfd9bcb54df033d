#pragma once
/// @file refusal.hpp
/// What a reference engine says when it cannot model a scene: not Bullet's own, so that every
/// reference engine (and the harness, which asks before it builds one) shares it.

#include <string>
#include <vector>

namespace clothbench::reference {

/// Why an engine cannot model a scene, and the scenario keys to blame, most specific first.
struct Refusal {
  std::string why;  // names the engine kind, the feature and what would be accepted
  std::vector<std::string> scene_keys;   // e.g. "cloth.stiffness.shear", "sphere.0.restitution"
  std::vector<std::string> engine_keys;  // the engine's own keys, e.g. "line_search"
};

}  // namespace clothbench::reference
