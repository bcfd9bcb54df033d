#include "harness/run/trajectory_files.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "harness/run/metrics.hpp"

namespace clothbench {

std::string npy_float32(const std::vector<size_t>& shape, const std::vector<float>& values) {
  std::string dims;
  for (size_t d : shape) dims += std::to_string(d) + ", ";
  if (shape.size() > 1) dims.resize(dims.size() - 1);  // "(3,)" but "(2, 3)"
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + dims + "), }";
  // magic (6) + version (2) + length (2) + header, padded with spaces to a multiple of 64
  const size_t total = (10 + header.size() + 1 + 63) / 64 * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(header.size() & 0xff);
  out += static_cast<char>(header.size() >> 8);
  out += header;
  const size_t at = out.size();
  out.resize(at + values.size() * sizeof(float));
  if (!values.empty()) std::memcpy(&out[at], values.data(), values.size() * sizeof(float));
  return out;
}

namespace {

/// Frames of the trajectory grid: every `stride`-th logged frame over the duration.
struct Grid {
  long long stride = 1;  // logged frames per trajectory frame
  size_t frames = 0;     // trajectory frames over the whole duration
};

Grid trajectory_grid(const Scenario& sc) {
  Grid g;
  g.stride = std::max(1LL, std::llround(sc.animation_interval / sc.frame_interval));
  g.frames = static_cast<size_t>(std::llround(sc.duration / sc.frame_interval) / g.stride) + 1;
  return g;
}

/// One engine's stable positions on the grid, flattened frame by particle by axis.
std::vector<float> engine_values(const EngineRun& run, const Grid& g, size_t* frames) {
  std::vector<float> v;
  *frames = 0;
  for (size_t k = 0; k < run.positions.size() && k < run.frames.size(); k += size_t(g.stride)) {
    if (!run.frames[k].stable) break;
    const cloth::Matrix3X& x = run.positions[k];
    for (Eigen::Index p = 0; p < x.cols(); ++p)
      for (int a = 0; a < 3; ++a) v.push_back(static_cast<float>(x(a, p)));
    ++*frames;
  }
  return v;
}

/// One collider of the trajectory: its motion, its reference point at t = 0 (a sphere's,
/// box's or cylinder's centre, a plane's point, a capsule's midpoint) and its JSON entry.
struct ShapeEntry {
  const cloth::Motion* motion;
  cloth::Vector3 origin;
  std::string json;
};

std::string vec_json(const cloth::Vector3& v) {
  return "[" + format_double(v(0)) + ", " + format_double(v(1)) + ", " + format_double(v(2)) + "]";
}

/// Every collider, in the order of the scene: spheres, planes, boxes, capsules, cylinders.
std::vector<ShapeEntry> shape_entries(const cloth::Scene& s) {
  std::vector<ShapeEntry> out;
  auto add = [&](const cloth::Collider& c, const cloth::Vector3& origin, std::string fields) {
    out.push_back({&c, origin, "{" + fields + ", \"margin\": " + format_double(c.margin) + "}"});
  };
  for (const cloth::Sphere& x : s.spheres)
    add(x, x.center, "\"type\": \"sphere\", \"radius\": " + format_double(x.radius));
  for (const cloth::HalfSpace& x : s.shapes.planes)
    add(x, x.point, "\"type\": \"plane\", \"normal\": " + vec_json(x.normal));
  for (const cloth::Box& x : s.shapes.boxes)
    add(x, x.center, "\"type\": \"box\", \"half_extents\": " + vec_json(x.half_extents));
  for (const cloth::Capsule& x : s.shapes.capsules)
    add(x, 0.5 * (x.a + x.b),
        "\"type\": \"capsule\", \"axis\": " + vec_json(x.b - x.a) +
            ", \"radius\": " + format_double(x.radius));
  for (const cloth::Cylinder& x : s.shapes.cylinders)
    add(x, x.center,
        "\"type\": \"cylinder\", \"radius\": " + format_double(x.radius) +
            ", \"height\": " + format_double(x.height));
  return out;
}

/// Every collider's reference point at every trajectory frame (frame by shape by axis).
std::vector<float> collider_values(const Scenario& sc, const Grid& g) {
  const std::vector<ShapeEntry> shapes = shape_entries(sc.scene);
  std::vector<float> v;
  for (size_t k = 0; k < g.frames; ++k) {
    const double t = double(k) * double(g.stride) * sc.frame_interval;
    for (const ShapeEntry& s : shapes) {
      const cloth::Vector3 c = s.origin + s.motion->displacement(t);
      for (int a = 0; a < 3; ++a) v.push_back(static_cast<float>(c(a)));
    }
  }
  return v;
}

/// The spring offsets (di, dj) of the kinds the cloth has, for the player's strain colour; a
/// mesh has none (its edges say it).
std::string springs_json(const cloth::ClothParams& c, bool mesh) {
  std::string s;
  if (mesh) return "[]";
  auto add = [&](const char* offsets) { s += std::string(s.empty() ? "" : ", ") + offsets; };
  if (c.k_structural > 0) add("[1, 0]");
  if (c.structural_v() > 0) add("[0, 1]");
  if (c.k_shear > 0) add("[1, 1], [1, -1]");
  if (c.k_bend > 0) add("[2, 0], [0, 2]");
  return "[" + s + "]";
}

/// A mesh's structural springs as a JSON array of [a, b, rest length (m)], for the player's
/// strain colour; null for a grid (its spring offsets say it).
std::string edges_json(const cloth::Model& model) {
  if (!model.is_mesh) return "null";
  std::string s = "[";
  bool first = true;
  for (const cloth::SpringLink& l : model.springs.links()) {
    if (l.kind == cloth::SpringKind::bend) continue;
    s += (first ? "[" : ", [") + std::to_string(l.a) + ", " + std::to_string(l.b) + ", " +
         format_double(l.rest) + "]";
    first = false;
  }
  return s + "]";
}

/// The cloth's triangles as a JSON array of [a, b, c] particle indices.
std::string triangles_json(const cloth::Model& model) {
  std::string s = "[";
  for (size_t k = 0; k < model.triangles.size(); ++k) {
    const cloth::Triangle& t = model.triangles[k];
    s += (k ? ", [" : "[") + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " +
         std::to_string(t[2]) + "]";
  }
  return s + "]";
}

/// An engine's frames with crossings as a JSON array of [frame, [triangle, ...]]: the
/// triangles pierced and those holding a piercing edge, at each trajectory frame that has any.
std::string crossings_json(const EngineRun& run, const Grid& g, size_t frames,
                           const cloth::SelfIntersectionMeter& meter) {
  std::string s = "[";
  std::vector<int> tris;
  for (size_t k = 0; k < frames; ++k) {
    const size_t logged = k * size_t(g.stride);
    if (logged >= run.positions.size()) break;
    // the count is known from frames.csv: only frames with crossings are measured again
    if (logged < run.frames.size() && run.frames[logged].self_intersections == 0) continue;
    meter.measure(run.positions[logged], &tris);
    if (tris.empty()) continue;
    s += std::string(s.size() > 1 ? ", [" : "[") + std::to_string(k) + ", [";
    for (size_t i = 0; i < tris.size(); ++i) s += (i ? ", " : "") + std::to_string(tris[i]);
    s += "]]";
  }
  return s + "]";
}

/// trajectory.json: what the .npy files hold.
std::string index_json(const RunResult& result, const Grid& g,
                       const std::vector<size_t>& engine_frames) {
  const cloth::SelfIntersectionMeter meter =
      cloth::rest_shape_meter(result.model.x0, result.model.triangles);
  const Scenario& sc = result.scenario;
  const cloth::ClothParams& c = sc.scene.cloth;
  std::ostringstream o;
  o << "{\n  \"format\": 1,\n  \"interval\": " << format_double(sc.animation_interval)
    << ",\n  \"frames\": " << g.frames << ",\n  \"particles\": " << result.model.particle_count()
    << ",\n  \"grid\": [" << result.model.nu << ", " << result.model.nv << "],\n  \"spacing\": ["
    << format_double(!result.model.is_mesh && c.nu > 1 ? c.size_u / (c.nu - 1) : 0) << ", "
    << format_double(!result.model.is_mesh && c.nv > 1 ? c.size_v / (c.nv - 1) : 0)
    << "],\n  \"springs\": " << springs_json(c, result.model.is_mesh)
    << ",\n  \"edges\": " << edges_json(result.model) << ",\n  \"reference\": \""
    << result.runs[static_cast<size_t>(result.reference)].spec.name << "\",\n  \"engines\": [";
  for (size_t i = 0; i < result.runs.size(); ++i) {
    const EngineRun& run = result.runs[i];
    o << (i ? "," : "") << "\n    {\"name\": \"" << run.spec.name << "\", \"file\": \""
      << run.spec.name << ".npy\", \"frames\": " << engine_frames[i]
      << ", \"stable\": " << (run.stable ? "true" : "false") << ", \"blowup_t\": "
      << (std::isnan(run.blowup_t) ? std::string("null") : format_double(run.blowup_t))
      << ", \"cause\": \"" << (run.timed_out ? "timeout" : run.cause)
      << "\", \"crossings\": " << crossings_json(run, g, engine_frames[i], meter) << "}";
  }
  o << "\n  ],\n  \"colliders_file\": \"colliders.npy\",\n  \"shapes\": [";
  const std::vector<ShapeEntry> shapes = shape_entries(sc.scene);
  for (size_t k = 0; k < shapes.size(); ++k) o << (k ? "," : "") << "\n    " << shapes[k].json;
  o << "\n  ],\n  \"held\": [";
  for (size_t p = 0, n = 0; p < sc.scene.held.size(); ++p)
    if (sc.scene.held[p]) o << (n++ ? ", " : "") << p;
  o << "],\n  \"triangles\": " << triangles_json(result.model) << "\n}\n";
  return o.str();
}

}  // namespace

void write_trajectories(const RunResult& result, const std::string& dir,
                        std::vector<std::unique_ptr<AtomicFile>>& pending) {
  const Scenario& sc = result.scenario;
  if (!(sc.animation_interval > 0) || result.runs.empty()) return;
  const Grid g = trajectory_grid(sc);
  const std::string folder = dir + "/trajectory/";
  make_directories(folder);
  const size_t particles = static_cast<size_t>(result.model.particle_count());
  std::vector<size_t> engine_frames;
  for (const EngineRun& run : result.runs) {
    size_t frames = 0;
    const std::vector<float> v = engine_values(run, g, &frames);
    engine_frames.push_back(frames);
    pending.push_back(std::make_unique<AtomicFile>(folder + run.spec.name + ".npy"));
    pending.back()->write(npy_float32({frames, particles, 3}, v));
  }
  pending.push_back(std::make_unique<AtomicFile>(folder + "colliders.npy"));
  pending.back()->write(
      npy_float32({g.frames, shape_entries(sc.scene).size(), 3}, collider_values(sc, g)));
  pending.push_back(std::make_unique<AtomicFile>(folder + "trajectory.json"));
  pending.back()->write(index_json(result, g, engine_frames));
}

}  // namespace clothbench
