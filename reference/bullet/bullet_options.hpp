#pragma once
/// @file bullet_options.hpp
/// Options of the Bullet engines (what an engine says when it cannot model a scene is
/// reference/refusal.hpp).

#include <optional>
#include <string>
#include <vector>

namespace clothbench::reference {

/// How bullet-softbody picks its link stiffness.
enum class SoftbodyStiffness {
  matched,  ///< the kLST that gives the scene's spring constant at the engine's dt
  klst      ///< BulletOptions::klst for every link
};

/// "matched" or "klst".
const char* softbody_stiffness_name(SoftbodyStiffness s);
/// The mode with that name, if any.
std::optional<SoftbodyStiffness> parse_softbody_stiffness(const std::string& name);
/// Every mode, in the order above.
const std::vector<SoftbodyStiffness>& all_softbody_stiffnesses();

/// Options of the Bullet engines (each kind reads its own).
struct BulletOptions {
  bool implicit = false;     // bullet-deformable: backward Euler instead of explicit
  bool line_search = false;  // bullet-deformable, implicit: Newton line search
  bool projection = true;    // bullet-deformable, implicit: contact projection
  SoftbodyStiffness stiffness = SoftbodyStiffness::matched;  // bullet-softbody
  double klst = 1.0;    // bullet-softbody: link stiffness in (0, 1] when stiffness = klst
  int iterations = 10;  // bullet-softbody: position-solver iterations
  double repulsion_stiffness = 0.5;  // bullet-deformable, self-collision: repulsion (N/m)
  double collision_margin = 0.0;     // bullet-deformable, self-collision: the soft body's
                                     // collision margin (m); 0: half the cloth's thickness
};

}  // namespace clothbench::reference
