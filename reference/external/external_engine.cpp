#include "reference/external/external_engine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

namespace clothbench::reference {
namespace {

/// Appends little-endian 8-byte fields (the harness runs on little-endian machines only).
struct Bytes {
  std::vector<char>& out;
  void f64(double v) { raw(&v, 8); }
  void i64(std::int64_t v) { raw(&v, 8); }
  void raw(const void* p, std::size_t n) {
    const char* c = static_cast<const char*>(p);
    out.insert(out.end(), c, c + n);
  }
  /// 3 by #P matrix, row by row (x row, y row, z row), as Matrix3X stores it.
  void rows(const cloth::Matrix3X& m) { raw(m.data(), sizeof(double) * size_t(m.size())); }
  void motion(const cloth::Motion& m) {
    for (int r = 0; r < 3; ++r) f64(m.velocity[r]);
    for (const auto& p : m.path)
      for (double v : p) f64(v);
  }
};

/// One collider record: type, path length, 8 geometry numbers, the response, the motion.
void add_collider(Bytes& b, std::int64_t type, const std::vector<double>& geometry,
                  const cloth::Collider& c) {
  b.i64(type);
  b.i64(static_cast<std::int64_t>(c.path.size()));
  for (size_t k = 0; k < 8; ++k) b.f64(k < geometry.size() ? geometry[k] : 0.0);
  b.f64(c.restitution);
  b.f64(c.friction);
  b.f64(c.margin);
  b.motion(c);
}

/// Every collider: spheres (0), planes (1), boxes (2), capsules (3), cylinders (4).
void add_colliders(Bytes& b, const cloth::Model& m) {
  for (const cloth::Sphere& s : m.spheres)
    add_collider(b, 0, {s.center[0], s.center[1], s.center[2], s.radius}, s);
  for (const cloth::HalfSpace& s : m.shapes.planes)
    add_collider(b, 1, {s.point[0], s.point[1], s.point[2], s.normal[0], s.normal[1], s.normal[2]},
                 s);
  for (const cloth::Box& s : m.shapes.boxes)
    add_collider(b, 2,
                 {s.center[0], s.center[1], s.center[2], s.half_extents[0], s.half_extents[1],
                  s.half_extents[2]},
                 s);
  for (const cloth::Capsule& s : m.shapes.capsules)
    add_collider(b, 3, {s.a[0], s.a[1], s.a[2], s.b[0], s.b[1], s.b[2], s.radius}, s);
  for (const cloth::Cylinder& s : m.shapes.cylinders)
    add_collider(b, 4, {s.center[0], s.center[1], s.center[2], s.radius, s.height}, s);
}

}  // namespace

std::vector<char> external_model_payload(const cloth::Model& m, double dt) {
  std::vector<char> out;
  Bytes b{out};
  const std::vector<cloth::SpringLink> links = m.springs.links();
  const int P = m.particle_count();
  const size_t colliders = m.spheres.size() + m.shapes.count();
  // counts, then the globals
  b.i64(P);
  b.i64(static_cast<std::int64_t>(links.size()));
  b.i64(static_cast<std::int64_t>(colliders));
  b.i64(static_cast<std::int64_t>(m.handles.size()));
  b.f64(dt);
  for (int r = 0; r < 3; ++r) b.f64(m.gravity[r]);
  b.f64(m.air_drag);
  for (int r = 0; r < 3; ++r) b.f64(m.wind[r]);
  // particles: rest positions, initial velocities, masses, free axes
  b.rows(m.x0);
  b.rows(cloth::Matrix3X::Zero(3, P));
  b.raw(m.mass.data(), sizeof(double) * size_t(P));
  b.rows(m.free);
  // springs: ends, rest lengths, stiffnesses, dampings
  for (const cloth::SpringLink& l : links) {
    b.i64(l.a);
    b.i64(l.b);
  }
  for (const cloth::SpringLink& l : links) b.f64(l.rest);
  for (const cloth::SpringLink& l : links) b.f64(l.stiffness);
  for (size_t s = 0; s < links.size(); ++s) b.f64(m.springs.damping);
  add_colliders(b, m);
  for (const cloth::Handle& h : m.handles) {
    b.i64(static_cast<std::int64_t>(h.particles.size()));
    b.i64(static_cast<std::int64_t>(h.motion.path.size()));
    for (int r = 0; r < 3; ++r) b.f64(h.motion.velocity[r]);
    for (int p : h.particles) b.i64(p);
    for (const auto& p : h.motion.path)
      for (double v : p) b.f64(v);
  }
  return out;
}

ExternalEngine::ExternalEngine(const ExternalOptions& options, const cloth::Scene& scene, double dt)
    : m_options(options) {
  const cloth::Model model = cloth::build_model(scene);
  m_particles = model.particle_count();
  m_x = model.x0;
  m_v = cloth::Matrix3X::Zero(3, m_particles);
  m_next_x.resize(3, m_particles);
  m_next_v.resize(3, m_particles);
  // the thread on its CPU before the spawn, so that the program starts on it
  if (options.share_cpu) m_pin = std::make_unique<CpuPin>();
  // room in the socket for a whole state (header, head, x and v), the largest message
  m_process =
      std::make_unique<ExternalProcess>(options.command, 16 + 32 + 48 * std::size_t(m_particles));
  // the handshake: both sides name the version they speak
  std::vector<char> hello(8, 0);
  std::memcpy(hello.data(), &kExternalProtocolVersion, 4);
  send(ExternalMessage::hello, hello);
  const std::vector<char> answer = receive(ExternalMessage::hello);
  std::uint32_t version = 0;
  if (answer.size() >= 4) std::memcpy(&version, answer.data(), 4);
  if (version != kExternalProtocolVersion)
    m_process->fail("speaks protocol version " + std::to_string(version) + ", the harness " +
                    std::to_string(kExternalProtocolVersion));
  send(ExternalMessage::model, external_model_payload(model, dt));
  receive(ExternalMessage::model);
}

void ExternalEngine::send(ExternalMessage type, const iovec* parts, int count) {
  m_deadline =
      ExternalProcess::Clock::now() + std::chrono::duration_cast<ExternalProcess::Clock::duration>(
                                          std::chrono::duration<double>(m_options.step_timeout));
  // the header, then the payload's parts: one write, so the engine wakes to a whole request
  char header[16];
  const std::uint32_t t = static_cast<std::uint32_t>(type);
  std::uint64_t n = 0;
  iovec all[4] = {{header, sizeof header}, {}, {}, {}};
  for (int k = 0; k < count && k < 3; ++k) {
    all[k + 1] = parts[k];
    n += parts[k].iov_len;
  }
  std::memcpy(header, kExternalMagic, 4);
  std::memcpy(header + 4, &t, 4);
  std::memcpy(header + 8, &n, 8);
  m_process->write(all, 1 + std::min(count, 3), m_deadline);
}

void ExternalEngine::send(ExternalMessage type, const std::vector<char>& payload) {
  const iovec part{const_cast<char*>(payload.data()), payload.size()};
  send(type, &part, 1);
}

std::pair<std::uint32_t, std::uint64_t> ExternalEngine::receive_header() {
  // sleep until the answer begins, then take its header
  char header[16];
  m_process->wait_readable(m_deadline);
  m_process->read(header, sizeof header, m_deadline);
  std::uint32_t t = 0;
  std::uint64_t n = 0;
  std::memcpy(&t, header + 4, 4);
  std::memcpy(&n, header + 8, 8);
  if (std::memcmp(header, kExternalMagic, 4) != 0)
    m_process->fail("answered something that is not a protocol frame (no CLBX header)");
  // a state is the largest answer; an error text is kept short
  const std::uint64_t limit = 64 + 48 * std::uint64_t(m_particles) + (1 << 16);
  if (n > limit) m_process->fail("announced an answer of " + std::to_string(n) + " bytes");
  return {t, n};
}

std::vector<char> ExternalEngine::receive(ExternalMessage expected) {
  const auto [t, n] = receive_header();
  if (t != static_cast<std::uint32_t>(expected)) reject(t, n, expected);
  std::vector<char> payload(n);
  m_process->read(payload.data(), payload.size(), m_deadline);
  return payload;
}

void ExternalEngine::reject(std::uint32_t type, std::uint64_t n, ExternalMessage expected) {
  std::vector<char> payload(n);
  m_process->read(payload.data(), payload.size(), m_deadline);
  if (type == static_cast<std::uint32_t>(ExternalMessage::error))
    m_process->fail("reported an error: " + std::string(payload.begin(), payload.end()));
  m_process->fail("answered a frame of type " + std::to_string(type) + " where type " +
                  std::to_string(static_cast<std::uint32_t>(expected)) + " was due");
}

void ExternalEngine::receive_state() {
  const auto [type, n] = receive_header();
  if (type != static_cast<std::uint32_t>(ExternalMessage::state))
    reject(type, n, ExternalMessage::state);
  const std::size_t bytes = sizeof(double) * 3 * std::size_t(m_particles);
  const std::size_t expected = 32 + 2 * bytes;
  if (n < 32) m_process->fail("answered a state shorter than its 32-byte head");
  // the head, then x and v straight into the spares when the size is right
  double head[4];
  if (n == expected) {
    const iovec parts[3] = {{head, 32}, {m_next_x.data(), bytes}, {m_next_v.data(), bytes}};
    m_process->read(parts, 3, m_deadline);
  } else {
    std::vector<char> p(n);
    m_process->read(p.data(), p.size(), m_deadline);
    std::memcpy(head, p.data(), 32);
  }
  std::int64_t evals = 0, count = 0;
  std::memcpy(&evals, &head[2], 8);
  std::memcpy(&count, &head[3], 8);
  if (count != m_particles || n != expected)
    m_process->fail("answered a state of " + std::to_string(count) + " particles in " +
                    std::to_string(n) + " bytes, where the model has " +
                    std::to_string(m_particles) + " particles (" + std::to_string(expected) +
                    " bytes)");
  if (!std::isfinite(head[0])) m_process->fail("answered a state at a time that is not finite");
  // the checked answer takes the place of the state (a swap of buffers, no copy)
  m_x.swap(m_next_x);
  m_v.swap(m_next_v);
  m_t = head[0];
  m_dissipated = std::isnan(head[1]) ? 0.0 : head[1];
  if (evals >= 0) m_counters.force_evals = evals;
}

void ExternalEngine::advance(double dt, int steps) {
  if (steps <= 0) return;
  const std::int64_t s = steps;
  const iovec parts[2] = {{const_cast<std::int64_t*>(&s), 8}, {&dt, 8}};
  send(ExternalMessage::step, parts, 2);
  receive_state();
  m_counters.steps += steps;
}

void ExternalEngine::set_state(const cloth::Matrix3X& x, const cloth::Matrix3X& v, double t) {
  // x and v go from the caller's matrices to the socket, no copy between
  const iovec parts[3] = {{&t, 8},
                          {const_cast<double*>(x.data()), sizeof(double) * std::size_t(x.size())},
                          {const_cast<double*>(v.data()), sizeof(double) * std::size_t(v.size())}};
  send(ExternalMessage::set_state, parts, 3);
  receive_state();
}

void ExternalEngine::read_state() {
  send(ExternalMessage::get_state);
  receive_state();
}

bool external_allowed() {
  const char* v = std::getenv(kAllowExternalVariable);
  return v && std::string(v) == "1";
}

std::string external_not_allowed_message(const std::string& engine_name) {
  return "engine " + engine_name +
         " runs an external program (kind = \"external\"), which clothbench runs only when "
         "allowed: add --allow-external to the command or set " +
         kAllowExternalVariable + "=1 in the environment";
}

}  // namespace clothbench::reference
