#pragma once
/// @file mass_spring_engine.hpp
/// The example external engine's physics, free of clothbench: a mass-spring cloth stepped by
/// symplectic Euler, built from the model message of the external-engine protocol, version 1
/// (docs/external-engines.md). Colliders are read and ignored; handles follow their paths.

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace example {

/// Reads 8-byte little-endian fields of a payload in order.
struct Fields {
  const char* data;
  std::size_t size, at = 0;
  template <class T>
  T next() {
    if (at + sizeof(T) > size) throw std::runtime_error("model message too short");
    T v;
    std::memcpy(&v, data + at, sizeof v);
    at += sizeof v;
    return v;
  }
  template <class T>
  std::vector<T> many(std::size_t n) {
    std::vector<T> out(n);
    for (T& v : out) v = next<T>();
    return out;
  }
};

/// A handle: particles moved along a velocity or a piecewise-linear path of [t, dx, dy, dz].
struct Handle {
  std::vector<std::int64_t> particles;
  std::array<double, 3> velocity{};
  std::vector<std::array<double, 4>> path;

  /// Displacement (m) at time t (s).
  std::array<double, 3> at(double t) const {
    if (path.empty()) return {velocity[0] * t, velocity[1] * t, velocity[2] * t};
    if (t >= path.back()[0]) return {path.back()[1], path.back()[2], path.back()[3]};
    std::size_t k = 1;
    while (path[k][0] < t) ++k;
    const double s = (t - path[k - 1][0]) / (path[k][0] - path[k - 1][0]);
    std::array<double, 3> d;
    for (int r = 0; r < 3; ++r)
      d[r] = path[k - 1][r + 1] + s * (path[k][r + 1] - path[k - 1][r + 1]);
    return d;
  }
};

/// The cloth: 3 by P arrays stored row by row (x[r * P + p]), as the protocol sends them.
class MassSpringEngine {
 public:
  /// Builds the cloth from a model message's payload.
  MassSpringEngine(const char* payload, std::size_t size) {
    Fields f{payload, size};
    P = f.next<std::int64_t>();
    const auto S = f.next<std::int64_t>(), C = f.next<std::int64_t>(), H = f.next<std::int64_t>();
    dt = f.next<double>();
    for (double& g : gravity) g = f.next<double>();
    drag = f.next<double>();
    for (double& w : wind) w = f.next<double>();
    x0 = f.many<double>(3 * P);
    v = f.many<double>(3 * P);
    mass = f.many<double>(P);
    free = f.many<double>(3 * P);
    ends = f.many<std::int64_t>(2 * S);
    rest = f.many<double>(S);
    k = f.many<double>(S);
    c = f.many<double>(S);
    for (std::int64_t i = 0; i < C; ++i) {
      f.next<std::int64_t>();
      const auto n_path = f.next<std::int64_t>();
      f.many<double>(14 + 4 * n_path);  // geometry, response, velocity, path: ignored
    }
    for (std::int64_t i = 0; i < H; ++i) {
      Handle h;
      const auto n = f.next<std::int64_t>(), n_path = f.next<std::int64_t>();
      for (double& u : h.velocity) u = f.next<double>();
      h.particles = f.many<std::int64_t>(n);
      h.path.resize(n_path);
      for (auto& row : h.path)
        for (double& u : row) u = f.next<double>();
      handles.push_back(h);
    }
    x = x0;
    force.assign(3 * P, 0.0);
  }

  /// One symplectic Euler step of h seconds.
  void step(double h) {
    for (const Handle& hd : handles) set_handle(hd, h, true);
    const double power = forces();
    for (std::int64_t r = 0; r < 3; ++r)
      for (std::int64_t p = 0; p < P; ++p) {
        const std::int64_t i = r * P + p;
        const double a = free[i] > 0.0 ? force[i] / mass[p] + gravity[r] : 0.0;
        v[i] += h * a;
        x[i] += h * v[i];
      }
    dissipated += h * power;
    t += h;
    for (const Handle& hd : handles) set_handle(hd, h, false);
  }

  std::int64_t P = 0;
  double dt = 0, drag = 0, t = 0, dissipated = 0;
  std::int64_t force_evals = 0;
  std::array<double, 3> gravity{}, wind{};
  std::vector<double> x0, x, v, mass, free, rest, k, c, force;
  std::vector<std::int64_t> ends;
  std::vector<Handle> handles;

 private:
  /// Spring, damper and drag forces into force; returns the power they dissipate (W).
  double forces() {
    ++force_evals;
    double power = 0.0;
    for (std::int64_t i = 0; i < 3 * P; ++i) force[i] = 0.0;
    for (std::size_t s = 0; s < rest.size(); ++s) {
      const std::int64_t a = ends[2 * s], b = ends[2 * s + 1];
      double d[3], dv = 0.0, len2 = 0.0;
      for (int r = 0; r < 3; ++r) {
        d[r] = x[r * P + b] - x[r * P + a];
        len2 += d[r] * d[r];
      }
      const double len = std::sqrt(len2);
      for (int r = 0; r < 3; ++r) dv += (v[r * P + b] - v[r * P + a]) * d[r];
      const double vr = dv / len;
      const double f = (k[s] * (len - rest[s]) + c[s] * vr) / len;
      for (int r = 0; r < 3; ++r) {
        force[r * P + a] += f * d[r];
        force[r * P + b] -= f * d[r];
      }
      power += c[s] * vr * vr;
    }
    if (drag != 0.0)
      for (std::int64_t r = 0; r < 3; ++r)
        for (std::int64_t p = 0; p < P; ++p) {
          const double rel = v[r * P + p] - wind[r];
          force[r * P + p] -= drag * rel;
          power += drag * rel * v[r * P + p];
        }
    return power;
  }

  /// Before the step (start): the handle's particles take the path's velocity over it; after
  /// it: they sit exactly on the path.
  void set_handle(const Handle& hd, double h, bool start) {
    const auto now = hd.at(t), next = hd.at(t + h);
    for (std::int64_t p : hd.particles)
      for (int r = 0; r < 3; ++r) {
        if (start) v[r * P + p] = (next[r] - now[r]) / h;
        if (!start) x[r * P + p] = x0[r * P + p] + now[r];
      }
  }
};

}  // namespace example
