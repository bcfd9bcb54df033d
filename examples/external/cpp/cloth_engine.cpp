/// @file cloth_engine.cpp
/// The example external engine in C++: mass_spring_engine.hpp behind the external-engine
/// protocol, version 1 (docs/external-engines.md), on stdin and stdout. Run by clothbench:
///   command = ["/path/to/clothbench-example-engine"]

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "mass_spring_engine.hpp"

namespace {

enum : std::uint32_t {
  kHello = 1,
  kModel = 2,
  kStep = 3,
  kGet = 4,
  kSet = 5,
  kState = 6,
  kError = 7
};

/// Reads exactly n bytes of stdin; false at its end.
bool read_all(void* data, std::size_t n) {
  char* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t r = ::read(0, p, n);
    if (r <= 0) return false;
    p += r;
    n -= std::size_t(r);
  }
  return true;
}

/// Writes n bytes to stdout.
void write_all(const void* data, std::size_t n) {
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t w = ::write(1, p, n);
    if (w <= 0) std::exit(1);
    p += w;
    n -= std::size_t(w);
  }
}

/// Sends one frame: the 16-byte header, then the payload.
void send(std::uint32_t type, const std::vector<char>& payload) {
  char head[16] = {'C', 'L', 'B', 'X'};
  const std::uint64_t n = payload.size();
  std::memcpy(head + 4, &type, 4);
  std::memcpy(head + 8, &n, 8);
  write_all(head, 16);
  write_all(payload.data(), payload.size());
}

/// The state answer: t, dissipated, force evaluations, #P, then x and v row by row.
std::vector<char> state(const example::MassSpringEngine& e) {
  std::vector<char> out(32 + 48 * std::size_t(e.P));
  std::memcpy(out.data(), &e.t, 8);
  std::memcpy(out.data() + 8, &e.dissipated, 8);
  std::memcpy(out.data() + 16, &e.force_evals, 8);
  std::memcpy(out.data() + 24, &e.P, 8);
  std::memcpy(out.data() + 32, e.x.data(), 24 * std::size_t(e.P));
  std::memcpy(out.data() + 32 + 24 * std::size_t(e.P), e.v.data(), 24 * std::size_t(e.P));
  return out;
}

}  // namespace

int main() {
  std::unique_ptr<example::MassSpringEngine> engine;
  std::vector<char> payload;
  for (;;) {
    char head[16];
    if (!read_all(head, 16)) return 0;  // the harness closed our input: done
    std::uint32_t type;
    std::uint64_t n;
    std::memcpy(&type, head + 4, 4);
    std::memcpy(&n, head + 8, 8);
    payload.resize(n);
    if (!read_all(payload.data(), n)) return 0;
    try {
      if (type == kHello) {
        const std::uint32_t hello[2] = {1, 0};
        send(kHello, std::vector<char>((const char*)hello, (const char*)hello + 8));
      } else if (type == kModel) {
        engine = std::make_unique<example::MassSpringEngine>(payload.data(), n);
        send(kModel, {});
      } else if (type == kStep) {
        std::int64_t steps;
        double dt;
        std::memcpy(&steps, payload.data(), 8);
        std::memcpy(&dt, payload.data() + 8, 8);
        for (std::int64_t s = 0; s < steps; ++s) engine->step(dt);
        send(kState, state(*engine));
      } else if (type == kSet) {
        const std::size_t bytes = 24 * std::size_t(engine->P);
        std::memcpy(&engine->t, payload.data(), 8);
        std::memcpy(engine->x.data(), payload.data() + 8, bytes);
        std::memcpy(engine->v.data(), payload.data() + 8 + bytes, bytes);
        send(kState, state(*engine));
      } else if (type == kGet) {
        send(kState, state(*engine));
      } else {
        throw std::runtime_error("unknown request type " + std::to_string(type));
      }
    } catch (const std::exception& e) {
      const std::string what = e.what();
      send(kError, std::vector<char>(what.begin(), what.end()));
    }
  }
}
