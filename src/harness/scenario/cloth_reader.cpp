#include "harness/scenario/cloth_reader.hpp"

#include <algorithm>
#include <filesystem>
#include <memory>

#include "cloth/analysis/self_intersection.hpp"
#include "cloth/model/mesh_generator.hpp"
#include "cloth/model/triangle_mesh.hpp"
#include "harness/io/obj_reader.hpp"
#include "harness/scenario/fabric_preset.hpp"

namespace clothbench {

namespace {

// the keys only a grid has, and what a mesh's cloth says instead
const Keys kGridOnlyKeys = {"particles", "size", "center", "plane"};

/// cloth.particles and cloth.size.
void read_grid_shape(const Reader& r, const At& at, cloth::ClothParams& c) {
  const toml::table& table = at.table;
  if (const toml::node* n = table.get("particles")) {
    const auto p = Reader::int_pair(*n, 1);
    if (!p && Reader::has_huge_integer(*n))
      r.fail(n, "cloth.particles",
             "too large: at most 10000000 particles in all, got " + describe(*n));
    if (!p) r.expected(*n, "cloth.particles", "an array of 2 integers >= 1");
    const long long total = static_cast<long long>((*p)[0]) * (*p)[1];
    if (total < 2) r.expected(*n, "cloth.particles", "at least 2 particles in all");
    if (total > 10'000'000) r.expected(*n, "cloth.particles", "at most 10000000 particles in all");
    c.nu = (*p)[0];
    c.nv = (*p)[1];
  }
  const auto size = r.number_pair(at, "size", {c.size_u, c.size_v}, kSize);
  for (int d = 0; d < 2; ++d) {
    // springs along a direction with several particles need a length to rest at
    const int count = d == 0 ? c.nu : c.nv;
    if (count > 1 && !(size[d] > 0))
      r.fail(table.get("size"), "cloth.size",
             std::string("expected a size > 0 along ") + (d == 0 ? "u" : "v") + ", which has " +
                 std::to_string(count) + " particles, got " + toml_double(size[d]));
  }
  c.size_u = size[0];
  c.size_v = size[1];
  c.center = r.vec3(at, "center", c.center);
  c.plane = *parse_plane(r.choice(at, "plane", plane_name(c.plane), kPlanes));
}

/// The mass, given one way only: particle_mass, total_mass or areal_density (a mesh: one of
/// the last two).
void read_mass(const Reader& r, const At& at, bool mesh, cloth::ClothParams& c) {
  const toml::node* pm = at.table.get("particle_mass");
  const toml::node* tm = at.table.get("total_mass");
  const toml::node* ad = at.table.get("areal_density");
  if ((pm != nullptr) + (tm != nullptr) + (ad != nullptr) > 1) {
    const auto [n, key] =
        blame({{ad, "cloth.areal_density"}, {tm, "cloth.total_mass"}, {pm, "cloth.particle_mass"}});
    r.fail(n, key,
           "expected one of particle_mass, total_mass and areal_density, got more (give the "
           "mass one way only)");
  }
  if (mesh && pm)
    r.fail(pm, "cloth.particle_mass",
           "a mesh's vertices weigh what their share of its area does: give areal_density "
           "(kg/m^2) or total_mass (kg) instead");
  if (mesh && !tm && !ad && !(c.areal_density > 0))  // a fabric gives areal_density
    r.fail(&at.table, "cloth.areal_density",
           "a mesh needs its mass: areal_density = kg/m^2 or total_mass = kg");
  c.particle_mass = r.number(at, "particle_mass", c.particle_mass, kMass);
  c.total_mass = r.number(at, "total_mass", c.total_mass, kMass);
  c.areal_density = r.number(at, "areal_density", c.areal_density, kMass);
}

/// cloth.bend_model and cloth.bending_rigidity, after the stiffness table: the hinge model
/// needs a rigidity and has no bend springs, the springs take no rigidity.
void read_bend_model(const Reader& r, const At& at, cloth::ClothParams& c) {
  const bool hinge = r.choice(at, "bend_model", "springs", kBendModels) == "hinge";
  const toml::node* rigidity = at.table.get("bending_rigidity");
  if (!hinge) {
    if (rigidity)
      r.fail(rigidity, "cloth.bending_rigidity",
             "applies to bend_model = \"hinge\"; bend springs take cloth.stiffness.bend (N/m)");
    return;
  }
  c.bend_model = cloth::BendModel::hinge;
  if (!rigidity && !(c.bending_rigidity > 0))  // a fabric gives the rigidity
    r.fail(&at.table, "cloth.bending_rigidity",
           "bend_model = \"hinge\" needs bending_rigidity = B (N m), > 0, or a fabric");
  c.bending_rigidity = r.number(at, "bending_rigidity", c.bending_rigidity, kPositive);
  // the hinge model replaces the bend springs
  const toml::table* st = r.table(at, "stiffness");
  if (const toml::node* bend = st ? st->get("bend") : nullptr; bend && c.k_bend > 0)
    r.fail(bend, "cloth.stiffness.bend",
           "bend_model = \"hinge\" has no bend springs: leave bend out of the table (or 0)");
  c.k_bend = 0.0;
}

/// cloth.stiffness's structural springs: structural (along u and v alike), or a grid's
/// structural_u and structural_v (a direction left out has none), never both forms. With a
/// fabric, structural left out keeps the fabric's.
void read_structural(const Reader& r, const At& sat, bool mesh, bool fabric,
                     cloth::ClothParams& c) {
  const toml::table& st = sat.table;
  const toml::node* u = st.get("structural_u");
  const toml::node* v = st.get("structural_v");
  const toml::node* per = u ? u : v;
  if (per && mesh)
    r.fail(per, u ? "cloth.stiffness.structural_u" : "cloth.stiffness.structural_v",
           "a mesh's structural springs lie along its edges, in no grid direction, so a mesh "
           "stays isotropic: give structural alone");
  if (!per) {
    c.k_structural = r.number(sat, "structural", fabric ? c.k_structural : 0.0, kNonNegative);
    c.k_structural_v = -1.0;
    return;
  }
  // the values first, so that a value out of range is named as such
  const double ku = r.number(sat, "structural_u", 0.0, kNonNegative);
  const double kv = r.number(sat, "structural_v", 0.0, kNonNegative);
  if (st.get("structural"))
    r.fail(per, u ? "cloth.stiffness.structural_u" : "cloth.stiffness.structural_v",
           "expected either structural (u and v alike) or structural_u and structural_v, got "
           "both forms");
  c.k_structural = ku;
  c.k_structural_v = kv;
}

/// cloth.stiffness, cloth.damping and cloth.air_drag; a mesh has no shear springs but a
/// generated grid lattice (lattice = "grid"), which has them on its squares' diagonals. With a
/// fabric, c holds its springs and each key given overrides one.
void read_material(const Reader& r, const At& at, const Scenario& s, bool fabric,
                   cloth::ClothParams& c) {
  const bool mesh = s.scene.mesh != nullptr;
  const bool lattice = mesh && !s.scene.mesh->cells.empty();
  // a stiffness table names the spring kinds there are; an omitted kind has no springs (with a
  // fabric: keeps the fabric's)
  if (const toml::table* st = r.table(at, "stiffness")) {
    const At sat{*st, "cloth.stiffness"};
    r.check_keys(sat, kStiffnessKeys);
    if (mesh && !lattice && st->get("shear"))
      r.fail(st->get("shear"), "cloth.stiffness.shear",
             "a mesh has no shear springs: one structural spring per edge and one bend spring "
             "per interior edge (but a [cloth.generate] lattice = \"grid\"); leave shear out");
    read_structural(r, sat, mesh, fabric, c);
    c.k_shear = r.number(sat, "shear", fabric && !mesh ? c.k_shear : 0.0, kNonNegative);
    c.k_bend = r.number(sat, "bend", fabric ? c.k_bend : 0.0, kNonNegative);
  } else if (mesh) {
    c.k_shear = 0.0;
  }
  read_bend_model(r, at, c);
  c.damping = r.number(at, "damping", c.damping, kNonNegative);
  c.air_drag = r.number(at, "air_drag", c.air_drag, kNonNegative);
  c.self_collision = r.boolean(at, "self_collision", c.self_collision);
  c.thickness = r.number(at, "thickness", c.thickness, kLength);
  c.self_friction = r.number(at, "self_friction", c.self_friction, kNonNegative);
}

/// The fabric cloth.fabric names in the shipped table, or null without the key.
const Fabric* read_fabric(const Reader& r, const At& at) {
  if (!at.table.get("fabric")) return nullptr;
  const std::string name = r.string(at, "fabric", "");
  const FabricTable& table = shipped_fabrics();
  if (const Fabric* f = table.find(name)) return f;
  r.fail(at.table.get("fabric"), "cloth.fabric",
         "unknown fabric " + toml_string(name) + suggest(name, table.names()) + " (" +
             table.source + ")");
}

/// Mass per area (kg/m^2) of the cloth as read: areal_density, or total_mass or particle_mass
/// over the area they cover.
double areal_density_of(const cloth::Scene& scene) {
  const cloth::ClothParams& c = scene.cloth;
  if (c.areal_density > 0) return c.areal_density;
  if (scene.mesh) {
    const cloth::VectorX m = cloth::lumped_masses(*scene.mesh, 1.0);
    return c.total_mass / m.sum();
  }
  const double hu = c.nu > 1 ? c.size_u / (c.nu - 1) : c.size_v / std::max(c.nv - 1, 1);
  const double hv = c.nv > 1 ? c.size_v / (c.nv - 1) : hu;
  if (c.total_mass > 0) return c.total_mass / (c.size_u * c.size_v);
  return c.particle_mass / (hu * hv);
}

/// The fabric's springs and bending on the cloth as read so far (its shape and mass); the
/// [cloth] keys read after this override them. Stretch springs the fabric has no data for are
/// the stiffness table's (or the defaults).
FabricSprings apply_fabric(const Reader& r, const At& at, const Fabric& f, Scenario& s) {
  cloth::ClothParams& c = s.scene.cloth;
  if (const toml::table* st = r.table(at, "stiffness")) {
    const At sat{*st, "cloth.stiffness"};
    c.k_structural = r.number(sat, "structural", c.k_structural, kNonNegative);
    c.k_shear = r.number(sat, "shear", c.k_shear, kNonNegative);
  }
  const bool hinge = r.choice(at, "bend_model", "springs", kBendModels) == "hinge";
  const double rho = areal_density_of(s.scene);
  const FabricSprings fs = s.scene.mesh
                               ? mesh_fabric_springs(f, *s.scene.mesh, c.k_structural, rho, hinge)
                               : grid_fabric_springs(f, c, rho, hinge);
  c.k_structural = fs.k_structural;
  c.k_shear = s.scene.mesh ? 0.0 : fs.k_shear;
  c.k_bend = fs.k_bend;
  c.bending_rigidity = fs.bending_rigidity;
  if (!fs.warning.empty())
    s.warnings.push_back("cloth.fabric = " + toml_string(f.name) + ": " + fs.warning);
  return fs;
}

/// [cloth.generate]: the shape and its sizes, each checked where it is read.
cloth::ShapeSpec read_shape(const Reader& r, const toml::table& t) {
  const At at{t, "cloth.generate"};
  r.check_keys(at, kGenerateKeys);
  cloth::ShapeSpec s;
  if (!t.get("shape"))
    r.fail(&t, "cloth.generate.shape", "expected shape = one of " + join(kShapes, "\""));
  s.shape = *parse_shape(r.choice(at, "shape", "disk", kShapes));
  const std::string name = cloth::mesh_shape_name(s.shape);
  // each shape takes its own size keys
  const Keys own = shape_keys(s.shape);
  for (const char* key : {"radius", "inner_radius", "size", "length"})
    if (const toml::node* n = t.get(key); n && !contains(own, key))
      r.fail(n, at.key(key), "applies to other shapes, not to shape = " + toml_string(name));
  for (std::string_view key : own)
    if (!t.get(key))
      r.fail(&t, at.key(key), "shape = " + toml_string(name) + " needs " + std::string(key));
  s.radius = r.number(at, "radius", s.radius, kLength);
  s.inner_radius = r.number(at, "inner_radius", s.inner_radius, kLength);
  const auto size = r.number_pair(at, "size", {s.size_u, s.size_v}, kLength);
  s.size_u = size[0];
  s.size_v = size[1];
  s.length = r.number(at, "length", s.length, kLength);
  if (!t.get("edge_length"))
    r.fail(&t, at.key("edge_length"), "expected edge_length = the target edge length (m)");
  s.edge_length = r.number(at, "edge_length", s.edge_length, kLength);
  s.seed = static_cast<std::uint64_t>(r.integer(at, "seed", 1, 0));
  s.center = r.vec3(at, "center", s.center);
  s.plane = *parse_plane(r.choice(at, "plane", plane_name(s.plane), kPlanes));
  const bool grid = r.choice(at, "lattice", "triangular", kLattices) == "grid";
  s.lattice = grid ? cloth::MeshLattice::grid : cloth::MeshLattice::triangular;
  s.lattice_angle = r.number(at, "lattice_angle", s.lattice_angle, kMultipleOf45);
  return s;
}

/// A warning when the mesh's rest shape already crosses itself (frames.csv counts those
/// crossings from frame 0 on).
void warn_rest_crossings(const cloth::TriangleMesh& mesh, Scenario& s) {
  // the meter the runs use
  const cloth::SelfIntersection si =
      cloth::rest_shape_meter(mesh.x, mesh.triangles).measure(mesh.x);
  if (si.crossings > 0)
    s.warnings.push_back(s.mesh.path + ": the rest shape crosses itself (" +
                         std::to_string(si.crossings) +
                         " edge-triangle crossings); frames.csv counts them from frame 0");
}

/// The mesh cloth.mesh names, resolved against the scenario file's folder.
std::shared_ptr<const cloth::TriangleMesh> read_mesh_file(const Reader& r, const At& at,
                                                          Scenario& s) {
  s.mesh.file = r.string(at, "mesh", "");
  if (s.mesh.file.empty()) r.expected(*at.table.get("mesh"), "cloth.mesh", "an OBJ file's path");
  namespace fs = std::filesystem;
  const fs::path file(s.mesh.file);
  const fs::path base = fs::path(s.source).parent_path();
  s.mesh.path =
      (file.is_absolute() || base.empty() ? file : base / file).lexically_normal().string();
  ObjFile obj = read_obj_file(s.mesh.path);
  for (std::string& w : obj.warnings) s.warnings.push_back(std::move(w));
  warn_rest_crossings(obj.mesh, s);
  return std::make_shared<const cloth::TriangleMesh>(std::move(obj.mesh));
}

/// A generated shape, whose size limit is the OBJ reader's.
std::shared_ptr<const cloth::TriangleMesh> generate(const Reader& r, const toml::table& t,
                                                    Scenario& s) {
  s.mesh.generated = true;
  s.mesh.shape = read_shape(r, t);
  // "edge_length: too small, ...": blamed on the key it names
  const std::string problem = cloth::shape_spec_problem(s.mesh.shape);
  if (!problem.empty()) {
    const std::string key = problem.substr(0, problem.find(':'));
    const toml::node* n = t.get(key);
    r.fail(n ? n : &t, "cloth.generate." + key, problem.substr(problem.find(':') + 2));
  }
  return std::make_shared<const cloth::TriangleMesh>(cloth::generate_mesh(s.mesh.shape));
}

}  // namespace

void read_cloth(const Reader& r, const toml::table* table, Scenario& s) {
  cloth::ClothParams& c = s.scene.cloth;
  c = cloth::ClothParams{};
  if (!table) return;
  const At at{*table, "cloth"};
  r.check_keys(at, kClothKeys);
  const toml::node* mesh = table->get("mesh");
  const toml::node* gen = table->get("generate");
  if (mesh && gen)
    r.fail(gen, "cloth.generate",
           "expected mesh = \"file.obj\" or a [cloth.generate] table, got both");
  if (mesh || gen) {
    // a mesh's vertices stand where its file (or its shape's centre and plane) puts them
    for (std::string_view key : kGridOnlyKeys)
      if (const toml::node* n = table->get(key))
        r.fail(n, at.key(key),
               std::string("applies to a grid, not to a mesh cloth (") +
                   (mesh ? "the vertices stand where the OBJ file puts them"
                         : "give center and plane in [cloth.generate]") +
                   ")");
    s.scene.mesh = mesh ? read_mesh_file(r, at, s) : generate(r, *r.table(at, "generate"), s);
  } else {
    read_grid_shape(r, at, c);
  }
  // a fabric's density unless the mass is given; its springs at the resolution and mass read
  const Fabric* fabric = read_fabric(r, at);
  // the presets' mapping is a grid's or a triangle mesh's, not a grid lattice's
  if (fabric && s.scene.mesh && !s.scene.mesh->cells.empty())
    r.fail(table->get("fabric"), "cloth.fabric",
           "expected no fabric on a [cloth.generate] lattice = \"grid\" (the presets are mapped "
           "onto grids and triangle meshes only); give its stiffness instead");
  const toml::table& t = *table;
  if (fabric && !t.get("areal_density") && !t.get("total_mass") && !t.get("particle_mass"))
    c.areal_density = fabric->areal_density;
  read_mass(r, at, s.scene.mesh != nullptr, c);
  const FabricSprings fs = fabric ? apply_fabric(r, at, *fabric, s) : FabricSprings{};
  read_material(r, at, s, fabric != nullptr, c);
  // the preset's damping follows the structural springs finally chosen
  if (fabric && !t.get("damping")) c.damping = fabric_damping(c.k_structural, fs.particle_mass);
}

}  // namespace clothbench
