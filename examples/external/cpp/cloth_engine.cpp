/// @file cloth_engine.cpp
/// The example external engine in C++: mass_spring_engine.hpp behind the external-engine
/// protocol, version 1 (docs/external-engines.md), on stdin and stdout. Run by clothbench:
///   command = ["/path/to/clothbench-example-engine"]

#include <sys/uio.h>
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

/// Writes the count parts to stdout in order, in one system call when the socket has room.
void write_all(iovec* parts, int count) {
  while (count > 0) {
    const ssize_t w = ::writev(1, parts, count);
    if (w <= 0) std::exit(1);
    // drop what was written from the front of the parts
    std::size_t done = std::size_t(w);
    while (count > 0 && done >= parts->iov_len) {
      done -= parts->iov_len;
      ++parts;
      --count;
    }
    if (count > 0) {
      parts->iov_base = static_cast<char*>(parts->iov_base) + done;
      parts->iov_len -= done;
    }
  }
}

/// Sends one frame: the 16-byte header, then the payload, as n bytes in the count parts (at
/// most 3); one write for the whole frame, so the harness wakes once to it.
void send(std::uint32_t type, const iovec* payload, int count) {
  char head[16] = {'C', 'L', 'B', 'X'};
  iovec all[4] = {{head, 16}, {}, {}, {}};
  std::uint64_t n = 0;
  for (int k = 0; k < count; ++k) {
    all[k + 1] = payload[k];
    n += payload[k].iov_len;
  }
  std::memcpy(head + 4, &type, 4);
  std::memcpy(head + 8, &n, 8);
  write_all(all, 1 + count);
}

/// Sends one frame of a payload in one piece.
void send(std::uint32_t type, const std::vector<char>& payload) {
  const iovec part{const_cast<char*>(payload.data()), payload.size()};
  send(type, &part, 1);
}

/// The state answer: t, dissipated, force evaluations, #P, then x and v row by row, written
/// straight from the engine's arrays (no copy, no allocation per answer).
void send_state(example::MassSpringEngine& e) {
  const double head[2] = {e.t, e.dissipated};
  const std::int64_t counts[2] = {e.force_evals, e.P};
  char head_bytes[32];
  std::memcpy(head_bytes, head, 16);
  std::memcpy(head_bytes + 16, counts, 16);
  const std::size_t bytes = 24 * std::size_t(e.P);
  const iovec parts[3] = {{head_bytes, 32}, {e.x.data(), bytes}, {e.v.data(), bytes}};
  send(kState, parts, 3);
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
        send_state(*engine);
      } else if (type == kSet) {
        const std::size_t bytes = 24 * std::size_t(engine->P);
        std::memcpy(&engine->t, payload.data(), 8);
        std::memcpy(engine->x.data(), payload.data() + 8, bytes);
        std::memcpy(engine->v.data(), payload.data() + 8 + bytes, bytes);
        send_state(*engine);
      } else if (type == kGet) {
        send_state(*engine);
      } else {
        throw std::runtime_error("unknown request type " + std::to_string(type));
      }
    } catch (const std::exception& e) {
      const std::string what = e.what();
      send(kError, std::vector<char>(what.begin(), what.end()));
    }
  }
}
