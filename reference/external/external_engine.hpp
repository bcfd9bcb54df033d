#pragma once
/// @file external_engine.hpp
/// A user's own engine behind the Simulator interface: a program the harness starts and speaks
/// protocol version 1 with on its stdin and stdout (docs/external-engines.md): a handshake, the
/// model once, then step, set-state and read-state requests, each answered by the state.

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "cloth/model/model.hpp"
#include "cloth/model/scene.hpp"
#include "cloth/model/simulator.hpp"
#include "reference/external/cpu_pin.hpp"
#include "reference/external/external_options.hpp"
#include "reference/external/external_process.hpp"

namespace clothbench::reference {

/// The protocol version this harness speaks.
constexpr std::uint32_t kExternalProtocolVersion = 1;

/// Message types of the protocol (the u32 after the magic of every frame header).
enum class ExternalMessage : std::uint32_t {
  hello = 1,      ///< both ways: u32 version, u32 flags (0)
  model = 2,      ///< harness to engine: the scene; the engine answers an empty model frame
  step = 3,       ///< harness to engine: i64 steps, f64 dt; answered by state
  get_state = 4,  ///< harness to engine: empty; answered by state
  set_state = 5,  ///< harness to engine: f64 t, 3 by #P x, 3 by #P v; answered by state
  state = 6,      ///< engine to harness: f64 t, f64 dissipated, i64 force_evals, i64 #P, x, v
  error = 7       ///< engine to harness: UTF-8 text; the run fails with it
};

/// The four bytes every frame header starts with.
constexpr char kExternalMagic[4] = {'C', 'L', 'B', 'X'};

/// The scene as the model message's payload (layout: docs/external-engines.md), for the
/// engine's initial state (rest positions, zero velocities).
/// @param dt  the engine's step (s)
std::vector<char> external_model_payload(const cloth::Model& model, double dt);

/// The external engine. Every request is bounded by options.step_timeout; a crash, a hang, an
/// answer that breaks the protocol or an early exit throws cloth::EngineFailure (the run fails,
/// other runs go on). The process is killed and reaped on destruction at the latest.
class ExternalEngine final : public cloth::Simulator {
 public:
  /// Starts options.command and sends it the model of scene stepped by dt (s). With
  /// options.share_cpu the calling thread is pinned to one CPU first, which the program
  /// inherits; the thread's previous CPUs come back when the engine is destroyed. The engine is
  /// to be stepped from the thread that built it.
  ExternalEngine(const ExternalOptions& options, const cloth::Scene& scene, double dt);

  void step(double dt) override { advance(dt, 1); }
  /// One step request for steps steps of dt (s).
  void advance(double dt, int steps) override;
  bool prefers_batches() const override { return true; }
  const cloth::Matrix3X& positions() const override { return m_x; }
  const cloth::Matrix3X& velocities() const override { return m_v; }
  double time() const override { return m_t; }
  /// What the engine reports in its state answers (J); 0 when it reports NaN (not kept).
  double dissipated() const override { return m_dissipated; }
  cloth::Counters counters() const override { return m_counters; }
  bool can_set_state() const override { return true; }
  /// One set-state request: the engine takes (x, v, t) and answers its state.
  /// @param x  3 by #P positions (m)
  /// @param v  3 by #P velocities (m/s)
  void set_state(const cloth::Matrix3X& x, const cloth::Matrix3X& v, double t) override;
  /// One read-state request (the engine's state is otherwise known from its last answer).
  void read_state();
  /// Process id of the engine (tests check it is reaped).
  int pid() const { return m_process->pid(); }
  /// The CPU the engine and the thread that built it share (share_cpu); -1 when they are not
  /// pinned (share_cpu false, or the system refused).
  int cpu() const { return m_pin ? m_pin->cpu() : -1; }

 private:
  /// Sends one frame of type whose payload is the count parts in order (at most 3), header and
  /// parts in one write.
  void send(ExternalMessage type, const iovec* parts = nullptr, int count = 0);
  /// Sends one frame of type and payload.
  void send(ExternalMessage type, const std::vector<char>& payload);
  /// Receives a frame header; checks its magic and announced size, returns its type and size.
  std::pair<std::uint32_t, std::uint64_t> receive_header();
  /// Receives one frame, checks its type is expected (an error frame fails the run with its
  /// text) and returns its payload.
  std::vector<char> receive(ExternalMessage expected);
  /// Receives the rest of a frame whose header said type and n bytes, for a frame that is not
  /// the one expected: an error frame fails the run with its text, any other with its type.
  [[noreturn]] void reject(std::uint32_t type, std::uint64_t n, ExternalMessage expected);
  /// Receives a state answer into m_x, m_v, m_t and the books: the positions and velocities
  /// straight from the socket into the spare matrices, which take their place once the answer
  /// is checked (no allocation, no copy in the harness).
  void receive_state();

  ExternalOptions m_options;
  std::unique_ptr<CpuPin> m_pin;  // before the process: the pin outlives the child
  std::unique_ptr<ExternalProcess> m_process;
  int m_particles = 0;
  cloth::Matrix3X m_x, m_v;
  cloth::Matrix3X m_next_x, m_next_v;  // 3 by #P spares the next state answer is read into
  double m_t = 0;
  double m_dissipated = 0;
  cloth::Counters m_counters;
  ExternalProcess::Clock::time_point m_deadline;  // of the request under way
};

}  // namespace clothbench::reference
