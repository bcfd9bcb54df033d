#pragma once
/// @file external_process.hpp
/// A child process the harness talks to over one stream socket (its stdin and stdout), with its
/// stderr kept in a bounded buffer, every wait bounded by a deadline, and the child always
/// reaped (killed first when it does not exit).

#include <poll.h>
#include <sys/uio.h>

#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace clothbench::reference {

/// A started program. Errors (a crash, a hang past the deadline, an early exit) throw
/// cloth::EngineFailure with the reason and the tail of the program's stderr.
class ExternalProcess {
 public:
  using Clock = std::chrono::steady_clock;

  /// Starts command[0] (looked up on PATH when it has no '/') with the arguments command[1..],
  /// no shell, by posix_spawnp (no fork of a threaded harness). The socket gets room for a
  /// message of message_bytes (B) each way where the system allows. Throws
  /// cloth::EngineFailure when it cannot be started.
  explicit ExternalProcess(const std::vector<std::string>& command, std::size_t message_bytes = 0);
  /// Closes the program's stdin, gives it a moment to exit, kills it if it does not, and reaps
  /// it.
  ~ExternalProcess();
  ExternalProcess(const ExternalProcess&) = delete;
  ExternalProcess& operator=(const ExternalProcess&) = delete;

  /// Writes n bytes to the program's stdin by the deadline.
  void write(const void* data, std::size_t n, Clock::time_point deadline);
  /// Writes the count parts in order to the program's stdin by the deadline, in one system call
  /// when the socket has room (so the program wakes once to a whole message).
  void write(const iovec* parts, int count, Clock::time_point deadline);
  /// Reads exactly n bytes of the program's stdout by the deadline.
  void read(void* data, std::size_t n, Clock::time_point deadline);
  /// Reads exactly as many bytes as the count parts hold, in order, by the deadline, straight
  /// into them (one system call when they have all arrived).
  void read(const iovec* parts, int count, Clock::time_point deadline);
  /// Waits by the deadline until the program's stdout has bytes to read (an answer under way),
  /// so that the reads after it do not find nothing first.
  void wait_readable(Clock::time_point deadline) { wait_for(POLLIN, deadline); }
  /// Kills the program, reaps it and throws cloth::EngineFailure with why, its exit status and
  /// its stderr tail.
  [[noreturn]] void fail(const std::string& why);
  /// The last bytes (at most kStderrTail) the program wrote to stderr.
  std::string stderr_tail() const { return m_stderr; }
  /// Process id of the child (0 once reaped).
  int pid() const { return m_pid; }

  /// Bytes of stderr kept.
  static constexpr std::size_t kStderrTail = 2000;

 private:
  /// Waits until the socket is ready for events (POLLIN or POLLOUT), draining stderr meanwhile;
  /// fails at the deadline.
  void wait_for(short events, Clock::time_point deadline);
  /// Spawns argv with sock as its stdin and stdout and err as its stderr; sets m_pid and returns
  /// 0, or returns the errno why it could not.
  int spawn(char* const* argv, int sock, int err);
  /// Reads what stderr has now into the tail buffer; false at its end.
  bool drain_stderr();
  /// Reaps the child if it has exited (waiting up to grace), else kills and reaps it; returns
  /// how it ended ("exited with status 1", "killed by signal 11").
  std::string reap(std::chrono::milliseconds grace);

  int m_pid = 0;
  int m_socket = -1;  // our end of the child's stdin and stdout
  int m_stderr_fd = -1;
  std::string m_stderr;
  std::string m_ended;  // how the child ended, once reaped
  std::string m_name;   // command[0], for messages
};

}  // namespace clothbench::reference
