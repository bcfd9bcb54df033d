#pragma once
/// @file scenario.hpp
/// A scenario: one physical scene, how long and how often to log it, and the engines to run.
/// Filled by scenario_loader from a TOML file; read by the runner and the engine factory.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cloth/model/mesh_generator.hpp"
#include "cloth/model/scene.hpp"
#include "cloth/solvers/solver_options.hpp"
#include "harness/scenario/engine_kind.hpp"
#include "reference/bullet/bullet_options.hpp"
#include "reference/external/external_options.hpp"
#include "reference/mujoco/mujoco_options.hpp"

namespace clothbench {

/// Which particles a constraint holds. A grid selects corners, edges, a disk, (i, j) indices,
/// a ball (within) or a box; a mesh a named vertex group, vertex indices, a ball or a box.
struct ConstraintSpec {
  std::string select = "corners";       // corners | edge:u0 | edge:u1 | edge:v0 | edge:v1 | disk |
                                        // indices | group | within | box
  std::uint8_t hold = cloth::kHoldAll;  // held axes (cloth::AxisBits)
  double disk_center_x = 0.0;           // m, select = "disk": centre in the cloth plane's
  double disk_center_z = 0.0;           // m   first and second world axes (x, z) or (x, y)
  double disk_radius = 0.0;             // m, select = "disk" or "within"
  std::vector<std::pair<int, int>> indices;  // select = "indices" on a grid: (i, j) pairs
  std::vector<int> vertices;                 // select = "indices" on a mesh: 0-based, file order
  std::string group;                         // select = "group": the mesh's group name
  cloth::Vector3 center = cloth::Vector3::Zero();   // m, select = "within": the ball's centre
  cloth::Vector3 box_min = cloth::Vector3::Zero();  // m, select = "box": lower corner
  cloth::Vector3 box_max = cloth::Vector3::Zero();  // m, select = "box": upper corner
};

/// A handle: the particles a selection picks, moved along a motion.
struct HandleSpec {
  ConstraintSpec select;  // hold is always xyz
  cloth::Motion motion;
};

/// One engine of a scenario.
struct EngineSpec {
  std::string name;   // unique within the scenario
  std::string label;  // what progress lines call it (a sweep's variant); empty: name
  EngineKind kind = EngineKind::custom;
  double dt = 1e-3;                     // s
  cloth::SolverOptions solver;          // kind = custom
  reference::BulletOptions bullet;      // kind = bullet-*
  reference::MujocoOptions mujoco;      // kind = mujoco
  reference::ExternalOptions external;  // kind = external
  std::optional<bool> self_collision;   // the engine's own setting; unset: the cloth's
  std::vector<std::pair<std::string, std::string>> overrides;  // its own scene keys: (key path
                                                               // as --set takes it, value as
                                                               // TOML text), in file order
  std::shared_ptr<const cloth::Scene> scene;  // the scene its overrides give (same rest shape and
                                              // held particles); null: the scenario's
};

/// Where a mesh cloth comes from: an OBJ file (cloth.mesh) or a generated shape
/// ([cloth.generate]); neither for a grid.
struct MeshSource {
  std::string file;        // cloth.mesh as written in the scenario
  std::string path;        // the file's path, resolved against the scenario's folder
  bool generated = false;  // [cloth.generate]
  cloth::ShapeSpec shape;  // what [cloth.generate] asks for

  bool any() const { return generated || !file.empty(); }
};

/// A textile standard test the harness measures on every engine's final state ([test]).
/// kind "cantilever" (ASTM D1388 option A, fixed overhang): the strip lies along +x and every
/// particle with rest x <= edge is held on all axes by the scene's own [[constraint]]s (the
/// loader checks it and adds none). kind "drape" (the Cusick test, BS 5058): a specimen hung
/// from a held support ([[constraint]] within or disk). kind "strip-tensile" (ISO 13934-1
/// strip): a grid held on all axes at one end (the clamp) and pulled along direction by its one
/// handle at the other; tensile.csv gets the force-strain curve. kind "bias-extension": a
/// generated grid lattice at 45 degrees, clamped alike and pulled along x (u); bias.csv gets
/// the force, angles and shear force. The metrics go to tests.csv.
struct TestSpec {
  std::string kind;             // "", "cantilever", "drape", "strip-tensile" or "bias-extension"
  double edge = 0.0;            // m, cantilever: the platform's edge along x
  std::string direction = "u";  // strip-tensile: the grid axis pulled along, "u" or "v"
  double fit_strain = 0.01;     // 1, strip-tensile: the strain range (0, fit_strain] of the slope
  std::string overhang_rule = "fixed";  // cantilever: "fixed" (the scene's overhang alone) or
                                        // "standard" (the sequence of overhangs to 41.5 deg)
  double fit_angle = 5.0;  // degrees, bias-extension: the angle range (0, fit_angle] of it
};

/// Everything a run needs; every key of the scenario file has a field here, and so has the
/// one run setting of the command line that is not a key (max_run_seconds).
struct Scenario {
  std::string name = "scenario";
  std::string description;
  std::string source;                 // file it came from, or "<embedded>"
  double duration = 1.0;              // s
  double frame_interval = 0.01;       // s between metric rows
  double snapshot_interval = 0.0;     // s between full-shape snapshots; 0: initial and final only
  double animation_interval = 0.03;   // s between trajectory frames, a whole number of frames
                                      // (default 1/30 s rounded so); 0: no trajectory
  double blowup_strain = 1.0;         // a run is unstable once a non-bend spring's stretch
                                      // l / l0 - 1 exceeds this
  double blowup_energy = 0.1;         // ... or once the energy error exceeds this times the
                                      // run's EnergyScale (see metrics.hpp)
  std::string reference;              // engine the others are compared against ("" = the first)
  cloth::Scene scene;                 // scene.held is filled from constraints
  MeshSource mesh;                    // where scene.mesh came from
  std::vector<std::string> warnings;  // what loading noticed but accepted (an unused vertex)
  std::vector<ConstraintSpec> constraints;
  std::vector<HandleSpec> handles;  // scene.handles is filled from these
  std::vector<EngineSpec> engines;
  TestSpec test;               // [test]; kind "" when the scenario has none
  double max_run_seconds = 0;  // s of wall clock one engine run may take before it stops as
                               // a timeout (--max-run-seconds; 0: no limit; never in a file)

  /// The reference engine's index in engines.
  int reference_index() const;
};

/// The scene engine e runs: its own (EngineSpec::scene) when its overrides give one, else s.scene.
const cloth::Scene& engine_scene(const Scenario& s, const EngineSpec& e);

/// Held-axis mask (#P entries) of the constraints on the cloth of scene (its grid or mesh;
/// within and box test rest positions).
/// Throws std::invalid_argument for a selection outside the grid or the mesh.
std::vector<std::uint8_t> held_mask(const cloth::Scene& scene,
                                    const std::vector<ConstraintSpec>& constraints);

}  // namespace clothbench
