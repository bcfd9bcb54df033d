#include "harness/scenario/scenario_schema.hpp"

#include <limits>
#include <sstream>

#include "cloth/model/scene.hpp"
#include "cloth/solvers/solver_options.hpp"
#include "format/number_format.hpp"
#include "harness/io/output_schema.hpp"
#include "harness/scenario/engine_kind.hpp"
#include "harness/scenario/scenario.hpp"
#include "harness/scenario/scenario_format.hpp"
#include "harness/scenario/toml_reader.hpp"
#include "reference/bullet/bullet_options.hpp"

namespace clothbench {

namespace {

using cloth::shortest_decimal;

constexpr long long kNoMax = std::numeric_limits<int>::max();

std::string vector_text(const cloth::Vector3& v) {
  return "[" + shortest_decimal(v.x()) + ", " + shortest_decimal(v.y()) + ", " +
         shortest_decimal(v.z()) + "]";
}

std::string quoted(const std::string& s) {
  return "\"" + s + "\"";
}

std::string one_of(const Keys& keys) {
  return "one of " + join(keys, "\"");
}

std::string boolean(bool b) {
  return b ? "true" : "false";
}

/// Adds rows to a table's list, the key lists' table at a time.
class Rows {
 public:
  explicit Rows(std::vector<ScenarioKey>& out, std::string table = "", std::string kind = "")
      : m_out(out), m_table(std::move(table)), m_kind(std::move(kind)) {}

  /// A number the loader checks against bound.
  void number(const char* key, const char* unit, double def, const Bound& bound,
              const char* meaning) {
    ScenarioKey k = row(key, "number", unit, shortest_decimal(def), meaning);
    k.range = *bound.text ? bound.text : "any finite number";
    k.bound = &bound;
    m_out.push_back(std::move(k));
  }
  /// A number whose default the loader derives (def says how).
  void number(const char* key, const char* unit, const std::string& def, const Bound& bound,
              const char* meaning) {
    number(key, unit, 0.0, bound, meaning);
    m_out.back().default_value = def;
  }
  /// An integer the loader checks to lie in [min, max] (max kNoMax: no upper limit).
  void integer(const char* key, long long def, long long min, long long max, const char* meaning,
               const std::string& def_text = "") {
    ScenarioKey k =
        row(key, "integer", "count", def_text.empty() ? std::to_string(def) : def_text, meaning);
    k.range = max == kNoMax ? ">= " + std::to_string(min)
                            : "[" + std::to_string(min) + ", " + std::to_string(max) + "]";
    k.integer = true;
    k.min = min;
    k.max = max;
    m_out.push_back(std::move(k));
  }
  /// A string that must be one of choices; def as shown (quoted).
  void choice(const char* key, const std::string& def, const Keys& choices, const char* meaning) {
    ScenarioKey k = row(key, "string", "", def, meaning);
    k.range = one_of(choices);
    m_out.push_back(std::move(k));
  }
  /// A point or vector [x, y, z] of any finite numbers.
  void vector(const char* key, const char* unit, const cloth::Vector3& def, const char* meaning) {
    other(key, "[x, y, z]", unit, vector_text(def), "any finite numbers", meaning);
  }
  /// Anything else: type, unit, default and range as text.
  void other(const char* key, const char* type, const char* unit, const std::string& def,
             const std::string& range, const char* meaning) {
    ScenarioKey k = row(key, type, unit, def, meaning);
    k.range = range;
    m_out.push_back(std::move(k));
  }

 private:
  ScenarioKey row(const char* key, const char* type, const char* unit, std::string def,
                  const char* meaning) const {
    ScenarioKey k;
    k.table = m_table;
    k.key = key;
    k.kind = m_kind;
    k.type = type;
    k.unit = unit;
    k.default_value = std::move(def);
    k.meaning = meaning;
    return k;
  }

  std::vector<ScenarioKey>& m_out;
  std::string m_table, m_kind;
};

void top_keys(std::vector<ScenarioKey>& out) {
  const Scenario s;
  const cloth::Scene scene;
  Rows r(out);
  r.other("name", "string", "", quoted(s.name), "letters, digits, '-', '_', '.'",
          "the scenario's name; it names the output folder");
  r.other("description", "string", "", "\"\"", "any", "one line saying what the scene shows");
  r.number("duration", "s", s.duration, kPositive,
           "simulated time of a run; a whole multiple of frame_interval");
  r.number("frame_interval", "s", s.frame_interval, kPositive,
           "time between logged frames (frames.csv rows); at most 1e7 frames per run");
  r.number("snapshot_interval", "s", s.snapshot_interval, kNonNegative,
           "time between full shapes in snapshots.csv, 0 or a whole multiple of frame_interval; "
           "0: the initial and final shapes only");
  r.number("animation_interval", "s", "1/30 s rounded to whole frames", kNonNegative,
           "time between trajectory frames, 0 or a whole multiple of frame_interval; 0: no "
           "trajectory");
  r.number("blowup_strain", "1", s.blowup_strain, kPositive,
           "a run is unstable once a structural or shear spring (a mesh's edge spring) stretches "
           "past this: l / l0 - 1 > blowup_strain");
  r.number("blowup_energy", "1", s.blowup_energy, kPositive,
           "a run is unstable once its energy error exceeds this times the run's energy scale");
  r.other("reference", "string", "", "the first engine", "an engine's name",
          "the engine the others are compared against");
  r.other("gravity", "[x, y, z]", "m/s^2", vector_text(scene.gravity),
          std::string(kAcceleration.text) + " each", "gravitational acceleration");
  r.vector("wind", "m/s", scene.wind, "air velocity; needs cloth.air_drag > 0");
  r.other("cloth", "table", "", "the default cloth", "",
          "the cloth (a grid or a triangle mesh) and its material");
  r.other("constraint", "array of tables", "", "none", "",
          "[[constraint]]: particles held in place, on some or all axes");
  r.other("handle", "array of tables", "", "none", "",
          "[[handle]]: particles moved along a prescribed motion");
  r.other("sphere", "array of tables", "", "none", "", "[[sphere]]: a rigid sphere collider");
  r.other("plane", "array of tables", "", "none", "", "[[plane]]: a rigid half-space collider");
  r.other("box", "array of tables", "", "none", "", "[[box]]: a rigid axis-aligned box collider");
  r.other("capsule", "array of tables", "", "none", "", "[[capsule]]: a rigid capsule collider");
  r.other("cylinder", "array of tables", "", "none", "",
          "[[cylinder]]: a rigid cylinder collider, axis along y");
  r.other("engine", "array of tables", "", "none", "at least one",
          "[[engine]]: an engine to run on the scene");
  r.other("test", "table", "", "none", "",
          "[test]: a textile standard test measured on every engine's final state (tests.csv)");
}

void test_keys(std::vector<ScenarioKey>& out) {
  const TestSpec t;
  Rows r(out, "test");
  r.choice("kind", "none (required)", kTestKinds,
           "the test: \"cantilever\" (ASTM D1388 option A, fixed overhang), \"drape\" (the "
           "Cusick test, BS 5058: a specimen hung from a support held by a [[constraint]] within "
           "or disk), \"strip-tensile\" (ISO 13934-1 strip) or \"bias-extension\" (a "
           "[cloth.generate] rectangle, lattice = \"grid\" at 45 degrees, clamped like the "
           "strip and pulled along x)");
  r.number("edge", "m", t.edge, kAnyNumber,
           "cantilever: the platform's edge; the strip lies along +x and every particle at rest "
           "x <= edge must be held on x, y and z by a [[constraint]]");
  r.choice("direction", quoted(t.direction), kTensileDirections,
           "strip-tensile: the grid axis pulled along, u (the grid's first index, x: warp) or v "
           "(its second: z, or y when plane = \"xy\"; weft); the particles held on x, y and z "
           "are the clamp, the one [[handle]] at the far end along it pulls");
  r.number("fit_strain", "1", t.fit_strain, kPositive,
           "strip-tensile: tensile_stiffness is the least-squares slope of force per width "
           "against strain over the frames with 0 < strain <= fit_strain");
  r.choice("overhang_rule", quoted(t.overhang_rule), kOverhangRules,
           "cantilever: \"fixed\" measures the scene's overhang alone; \"standard\" also finds "
           "the overhang at which the settled chord angle reaches 41.5 degrees (ASTM D1388, BS "
           "3356) by a sequence of settled runs with the held edge moved column by column, and "
           "reports c = l / 2 there (bending_length_standard, overhangs.csv)");
  r.number("fit_angle", "degrees", t.fit_angle, kPositive,
           "bias-extension: shear_stiffness is the least-squares slope of shear force per unit "
           "length against the central zone's measured shear angle over the frames with "
           "0 < angle <= fit_angle");
}

void generate_keys(std::vector<ScenarioKey>& out) {
  const cloth::ShapeSpec g;
  Rows r(out, "cloth.generate");
  r.choice("shape", "none (required)", kShapes,
           "a disk, an annulus, a rectangle of irregular triangles, or a tube along y");
  r.number("radius", "m", "none (disk, annulus, tube)", kLength, "outer radius");
  r.number("inner_radius", "m", "none (annulus)", kLength, "the hole's radius, below radius");
  r.other("size", "[u, v] numbers", "m", "none (rectangle)", std::string(kLength.text) + " each",
          "extent along the plane's two axes");
  r.number("length", "m", "none (tube)", kLength, "the tube's length along y");
  r.number(
      "edge_length", "m", "none (required)", kLength,
      "target edge length of the triangles: at least six edges around a disk or tube "
      "(at most 2 pi radius / 6), one across an annulus's ring and a rectangle's shorter side");
  r.integer("seed", 1, 0, kNoMax, "the jitter's seed: the same seed gives the same mesh");
  r.vector("center", "m", g.center, "centre of the shape");
  r.choice("plane", quoted(plane_name(g.plane)), kPlanes,
           "disk, annulus, rectangle: xz horizontal, xy vertical");
  r.choice("lattice", quoted(cloth::mesh_lattice_name(g.lattice)), kLattices,
           "rectangle: \"triangular\" (jittered, Delaunay) or \"grid\": squares of side "
           "edge_length (yarns) split in two triangles, springs like a grid's (structural along "
           "the yarns, shear on both diagonals, bend two sides apart); the rectangle's edges cut "
           "squares in half at 45 degrees");
  r.number("lattice_angle", "degrees", g.lattice_angle, kMultipleOf45,
           "lattice = \"grid\": the yarns' angle to u, a multiple of 45 (45: a bias specimen)");
}

void cloth_keys(std::vector<ScenarioKey>& out) {
  const cloth::ClothParams c;
  Rows r(out, "cloth");
  r.other("particles", "[nu, nv] integers", "count",
          "[" + std::to_string(c.nu) + ", " + std::to_string(c.nv) + "]",
          ">= 1 each, 2 to 10000000 in all", "particles along u and v");
  r.other("size", "[u, v] numbers", "m",
          "[" + shortest_decimal(c.size_u) + ", " + shortest_decimal(c.size_v) + "]",
          std::string(kSize.text) + " each, > 0 along a direction with several particles",
          "extent of the flat cloth along u and v");
  r.vector("center", "m", c.center, "centre of the flat initial cloth");
  r.choice("plane", quoted(plane_name(c.plane)), kPlanes,
           "orientation of the initial cloth: xz horizontal, xy vertical");
  r.number("particle_mass", "kg", c.particle_mass, kMass,
           "mass of each particle (not with total_mass)");
  r.number("total_mass", "kg", "particle_mass times the particles", kMass,
           "mass of the whole cloth, spread evenly (a mesh: by area); one way of giving the mass");
  r.number("areal_density", "kg/m^2", "none", kMass,
           "mass per area: a grid's size area or a mesh's triangles' times this; one way of "
           "giving the mass");
  r.other("mesh", "string", "", "none (a grid)", "an OBJ file's path",
          "a triangle mesh instead of particles, size, center and plane; relative to the "
          "scenario file");
  r.other("generate", "table", "", "none (a grid)", "",
          "[cloth.generate]: a shape the tool triangulates instead of a grid or a mesh file");
  r.other("stiffness", "table", "", "every kind at " + shortest_decimal(c.k_structural) + " N/m",
          "",
          "spring constants by kind; a kind left out of the table has no springs. The same "
          "constants on a mesh and on a grid are different fabrics: the springs per area differ");
  r.other("bend_model", "string", "", "\"springs\"", "one of \"springs\", \"hinge\"",
          "how the cloth resists bending: bend springs (cloth.stiffness.bend), or the hinge "
          "model's quadratic bending energy with bending_rigidity and no bend springs (custom "
          "engine: not with xpbd or projective; refused by the Bullet engines)");
  r.other("bending_rigidity", "number", "N m", "none", "> 0; only with bend_model = \"hinge\"",
          "the hinge model's bending rigidity B per unit width: a sheet bent to curvature k stores "
          "B k^2 / 2 per unit area");
  r.other("fabric", "string", "", "none", "a name in reference/fabrics/fabrics.toml",
          "a fabric preset: sets areal_density, the stiffness table, bending_rigidity (hinge) "
          "and damping from published measurements at the cloth's resolution "
          "(docs/fabrics.md); keys given here override the preset's, one by one");
  r.number("damping", "N s/m", c.damping, kNonNegative, "damper along every spring");
  r.number("air_drag", "N s/m", c.air_drag, kNonNegative,
           "viscous drag of every particle against the wind");
  r.other("self_collision", "boolean", "", boolean(c.self_collision), "true or false",
          "keep the cloth's layers apart in every engine that can (an engine's own "
          "self_collision overrides it); a thickness the rest shape violates is refused");
  r.number("thickness", "m", c.thickness, kLength,
           "self-contact: the distance kept between layers (elements more than two rings apart)");
  r.number("self_friction", "1", c.self_friction, kNonNegative,
           "self-contact: Coulomb coefficient of cloth on cloth");
  Rows st(out, "cloth.stiffness");
  st.number("structural", "N/m", 0.0, kNonNegative,
            "springs between grid neighbours along u and v, or along a mesh's edges (0 when the "
            "table leaves it out)");
  st.number("structural_u", "N/m", 0.0, kNonNegative,
            "a grid's structural springs along u (its first index i: x, the warp of a woven "
            "fabric), instead of structural; a mesh refuses it (meshes stay isotropic)");
  st.number("structural_v", "N/m", 0.0, kNonNegative,
            "a grid's structural springs along v (its second index j: z, or y when plane = "
            "\"xy\"; the weft), with structural_u; a direction left out has no springs");
  st.number("shear", "N/m", 0.0, kNonNegative,
            "springs along the grid's diagonals; a mesh has none (an error there)");
  st.number("bend", "N/m", 0.0, kNonNegative,
            "springs between particles two apart along u and v; on a mesh one across each "
            "interior edge, joining the two vertices opposite it");
  generate_keys(out);
}

void selection_keys(std::vector<ScenarioKey>& out, const char* table, bool hold) {
  const ConstraintSpec c;
  Rows r(out, table);
  r.choice("select", quoted(c.select) + " (a mesh: \"group\")", kSelections,
           "which particles: on a grid the four corners, one edge, a disk or grid indices; on a "
           "mesh a vertex group or vertex indices; on either a ball (within) or a box of rest "
           "positions");
  if (hold)
    r.other("hold", "string", "", quoted(hold_letters(c.hold)),
            "a non-empty combination of x, y, z", "the world axes held");
  r.other("center", "[a, b] or [x, y, z] numbers", "m", "none (required by disk, within)",
          "any finite numbers",
          "select = \"disk\": centre on the cloth plane's two axes (x, z or x, y); select = "
          "\"within\": the ball's centre");
  r.number("radius", "m", "none (required by disk, within)", kLength,
           "select = \"disk\" or \"within\": radius; it must hold a particle");
  r.other("list", "[[i, j], ...] or [v, ...]", "count", "none (required by indices)",
          "indices on the grid or the mesh",
          "select = \"indices\": a grid's (i, j) indices, or a mesh's 0-based vertex indices "
          "in file order");
  r.other("name", "string", "", "none (required by group)", "a g or o name of the mesh's file",
          "select = \"group\": the vertices of that group's faces");
  r.other("min", "[x, y, z] numbers", "m", "none (required by box)", "any finite numbers",
          "select = \"box\": the box's lower corner; rest positions inside are held");
  r.other("max", "[x, y, z] numbers", "m", "none (required by box)", ">= min on every axis",
          "select = \"box\": the box's upper corner");
}

void motion_keys(Rows& r, bool velocity) {
  const cloth::Motion m;
  if (velocity) r.vector("velocity", "m/s", m.velocity, "constant velocity (not with path)");
  r.other("path", "[[t, dx, dy, dz], ...]", "s, m", "none",
          "from [0, 0, 0, 0], times strictly increasing",
          "displacements at times, linear between them, held after the last");
}

void collider_keys(std::vector<ScenarioKey>& out, const char* table) {
  const cloth::Collider c;
  Rows r(out, table);
  r.number("restitution", "1", c.restitution, kUnitInterval,
           "restitution coefficient: 0 no bounce, 1 elastic");
  r.number("friction", "1", c.friction, kNonNegative, "Coulomb friction coefficient");
  r.number("margin", "m", c.margin, kShell, "contact shell thickness");
  motion_keys(r, true);
}

void shape_keys(std::vector<ScenarioKey>& out) {
  const cloth::Sphere sphere;
  Rows s(out, "sphere");
  s.vector("center", "m", sphere.center, "centre at t = 0");
  s.number("radius", "m", sphere.radius, kLength, "radius");
  collider_keys(out, "sphere");
  const cloth::HalfSpace plane;
  Rows p(out, "plane");
  p.vector("point", "m", plane.point, "a point on the plane at t = 0");
  p.other("normal", "[x, y, z]", "1", vector_text(plane.normal), "non-zero",
          "normal out of the solid (normalised)");
  collider_keys(out, "plane");
  const cloth::Box box;
  Rows b(out, "box");
  b.vector("center", "m", box.center, "centre at t = 0");
  b.other("half_extents", "[x, y, z]", "m", vector_text(box.half_extents),
          std::string(kLength.text) + " each", "half the box's size along each axis");
  collider_keys(out, "box");
  const cloth::Capsule capsule;
  Rows c(out, "capsule");
  c.vector("a", "m", capsule.a, "one end of the axis at t = 0");
  c.other("b", "[x, y, z]", "m", vector_text(capsule.b), "different from a",
          "the other end of the axis");
  c.number("radius", "m", capsule.radius, kLength, "radius around the axis");
  collider_keys(out, "capsule");
  const cloth::Cylinder cylinder;
  Rows y(out, "cylinder");
  y.vector("center", "m", cylinder.center, "centre at t = 0");
  y.number("radius", "m", cylinder.radius, kLength, "radius");
  y.number("height", "m", cylinder.height, kLength, "height along y");
  collider_keys(out, "cylinder");
}

void custom_engine_keys(std::vector<ScenarioKey>& out) {
  const cloth::SolverOptions o;
  cloth::SolverOptions ls = cloth::line_search_options();  // newton = "line-search", the default
  ls.contacts = cloth::kScenarioLineSearchContacts;
  const auto both = [](const std::string& linearized, const std::string& line_search) {
    return line_search + " (line-search, trust-region); otherwise " + linearized;
  };
  Rows r(out, "engine", engine_kind_name(EngineKind::custom));
  r.choice("integrator", quoted(cloth::integrator_name(o.integrator)), integrator_names(),
           "the time integrator");
  r.choice("newton", quoted(cloth::newton_method_name(cloth::kScenarioNewton)), kNewtonMethods,
           "implicit-euler: Newton steps from the old state, or on the incremental potential "
           "with a line search or in a trust region (Steihaug-Toint CG on the exact Hessian, "
           "region in the mass norm); an engine of another integrator that a sweep turns into "
           "implicit-euler keeps \"linearized\" unless it names newton");
  r.integer("newton_iterations", o.newton_iterations, 1, kNoMax,
            "implicit-euler: Newton iterations per step (line-search, trust-region: a limit)",
            both(std::to_string(o.newton_iterations), std::to_string(ls.newton_iterations)));
  r.number("newton_tolerance", "m/s^2", o.newton_tolerance, kPositive,
           "implicit-euler, line-search, trust-region: largest |M^-1 residual| / h a step ends "
           "at");
  r.choice("linear_solver", quoted(cloth::linear_solver_name(o.linear_solver)), kLinearSolvers,
           "implicit-euler: the solver of each Newton system");
  r.number("cg_tolerance", "1",
           both(shortest_decimal(o.cg_tolerance), shortest_decimal(ls.cg_tolerance)), kPositive,
           "implicit-euler: relative residual each linear system is solved to");
  r.integer("cg_max_iterations", o.cg_max_iterations, 1, kNoMax,
            "implicit-euler: conjugate-gradient iterations per system, at most");
  r.choice("cg_forcing",
           both(quoted(cloth::cg_forcing_name(o.cg_forcing)),
                quoted(cloth::cg_forcing_name(ls.cg_forcing))),
           kCgForcings,
           "implicit-euler: fixed tolerance, or Eisenstat and Walker's adaptive forcing "
           "(line-search, trust-region only)");
  r.choice("contacts",
           both(quoted(cloth::contact_mode_name(o.contacts)),
                quoted(cloth::contact_mode_name(ls.contacts))),
           kContactModes,
           "implicit-euler: contacts resolved after the step, inside the Newton solve as held "
           "normal velocities, or as a barrier potential in the step's objective (both "
           "line-search, trust-region only)");
  r.other("clamp_compressed", "boolean", "", boolean(o.clamp_compressed), "true or false",
          "implicit-euler: drop the negative transverse stiffness of compressed springs "
          "(trust-region: only in its preconditioner)");
  r.integer("clamped_iterations", o.clamped_iterations, 0, kNoMax,
            "implicit-euler, line-search: Newton iterations on the clamped matrix before the "
            "exact one");
  r.integer("substeps", o.substeps, 1, kMaxSolverIterations, "xpbd: substeps per step");
  r.integer("iterations", o.iterations, 1, kMaxSolverIterations,
            "xpbd: sweeps per substep; projective: local/global iterations per step");
}

/// The mujoco engine's keys.
void mujoco_engine_keys(std::vector<ScenarioKey>& out) {
  const reference::MujocoOptions m;
  Rows r(out, "engine", engine_kind_name(EngineKind::mujoco));
  r.choice("integrator", quoted(reference::mujoco_integrator_name(m.integrator)),
           kMujocoIntegrators,
           "MuJoCo's integrator (implicit: in the damping only, the springs stay explicit)");
  r.number("margin", "m", "each collider's margin", kPositive,
           "contact shell of every collider (particles are spheres of half the smallest)");
  r.number("friction", "1", "each collider's friction", kNonNegative,
           "Coulomb coefficient of every collider");
  r.other("solref", "array of 2 numbers", "s, 1", "[0.02, 1]", "each > 0",
          "MuJoCo's contact solref: time constant and damping ratio");
  r.other("solimp", "array of 3 numbers", "1, 1, m", "[0.9, 0.95, 0.001]",
          "d0, dwidth in (0, 1), width > 0", "MuJoCo's contact solimp");
  r.choice("cone", "\"pyramidal\"", {"pyramidal", "elliptic"}, "MuJoCo's friction cone");
}

void engine_keys(std::vector<ScenarioKey>& out) {
  const EngineSpec e;
  Rows r(out, "engine");
  r.other("name", "string", "", "custom-<integrator>, or the kind",
          "letters, digits, '-', '_', '+'; unique", "the engine's name in outputs and --set keys");
  r.choice("kind", quoted(engine_kind_name(e.kind)), engine_kind_names(), "the kind of engine");
  r.number("dt", "s", e.dt, kPositive, "time step; frame_interval must be a whole multiple of it");
  r.other("self_collision", "boolean", "", "the cloth's self_collision", "true or false",
          "this engine's self-contact, overriding the cloth's; true is refused on "
          "bullet-softbody and mujoco, which have none");
  r.other("overrides", "table", "", "{}",
          "--set key paths under cloth, gravity, wind and the colliders; same rest shape and "
          "held particles",
          "this engine's own scene values, e.g. { \"cloth.stiffness.bend\" = 3.2 } (what "
          "clothbench fit writes); the others run the file's");
  custom_engine_keys(out);
  const reference::BulletOptions b;
  Rows d(out, "engine", engine_kind_name(EngineKind::bullet_deformable));
  d.other("implicit", "boolean", "", boolean(b.implicit), "true or false",
          "backward Euler instead of explicit");
  d.other("line_search", "boolean", "", boolean(b.line_search), "true or false",
          "implicit: Newton with a line search");
  d.other("projection", "boolean", "", boolean(b.projection), "true or false",
          "implicit: contact projection");
  d.number("repulsion_stiffness", "N/m", b.repulsion_stiffness, kPositive,
           "self-collision: the stiffness of Bullet's repulsion between a node and a face");
  d.number("collision_margin", "m", "half the cloth's thickness", kNonNegative,
           "self-collision: the soft body's collision margin (0: the default)");
  Rows s(out, "engine", engine_kind_name(EngineKind::bullet_softbody));
  s.choice("stiffness", quoted(reference::softbody_stiffness_name(b.stiffness)), kSoftbodyStiffness,
           "link stiffness: matched to the spring constant at dt, or klst for every link");
  s.number("klst", "1", b.klst, kUnitInterval, "stiffness = \"klst\": Bullet's link stiffness");
  s.integer("iterations", b.iterations, 1, kNoMax, "position-solver iterations per step");
  mujoco_engine_keys(out);
  const reference::ExternalOptions x;
  Rows ext(out, "engine", engine_kind_name(EngineKind::external));
  ext.other("command", "array of strings", "", "required", "a non-empty array of non-empty strings",
            "the program and its arguments, run without a shell; words naming a file or folder "
            "relative to the scenario file's folder are resolved against it "
            "(docs/external-engines.md)");
  ext.number("step_timeout", "s", x.step_timeout, kPositive,
             "wall clock the program has to answer one request before it is killed");
  ext.other("share_cpu", "boolean", "", boolean(x.share_cpu), "true or false",
            "the run's thread and the program on one CPU for the run (less protocol overhead "
            "for a single-threaded program; a multi-threaded one would be slowed: "
            "docs/external-engines.md)");
}

}  // namespace

const std::vector<ScenarioKey>& scenario_keys() {
  static const std::vector<ScenarioKey> keys = [] {
    std::vector<ScenarioKey> out;
    top_keys(out);
    cloth_keys(out);
    selection_keys(out, "constraint", true);
    selection_keys(out, "handle", false);
    Rows handle(out, "handle");
    motion_keys(handle, false);
    shape_keys(out);
    test_keys(out);
    engine_keys(out);
    return out;
  }();
  return keys;
}

std::string scenario_schema_markdown() {
  std::ostringstream o;
  o << "| key | type | unit | default | range | meaning |\n|---|---|---|---|---|---|\n";
  for (const ScenarioKey& k : scenario_keys()) {
    o << "| `" << k.path() << "`" << (k.kind.empty() ? "" : " (" + k.kind + ")") << " | " << k.type
      << " | " << (k.unit.empty() ? "-" : k.unit) << " | " << markdown_cell(k.default_value)
      << " | " << markdown_cell(k.range.empty() ? "-" : k.range) << " | "
      << markdown_cell(k.meaning) << " |\n";
  }
  return o.str();
}

}  // namespace clothbench
