#include "reference/external/external_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "cloth/model/simulator.hpp"

extern char** environ;

namespace clothbench::reference {
namespace {

/// Closes fd if open and marks it closed.
void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

/// Milliseconds left until deadline (0 when past), for poll.
int ms_left(ExternalProcess::Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
      deadline - ExternalProcess::Clock::now());
  return left.count() <= 0 ? 0 : static_cast<int>(std::min<long long>(left.count() + 1, 60000));
}

/// Gives the socket sock room for a message of bytes (plus a margin) in flight, so that a whole
/// state answer is written in one go; never shrinks it, and the kernel caps it at its limit
/// (net.core.wmem_max).
void make_room(int sock, std::size_t bytes) {
  int size = 0;
  socklen_t len = sizeof size;
  if (::getsockopt(sock, SOL_SOCKET, SO_SNDBUF, &size, &len) != 0) return;
  // the kernel reports double what was asked (its bookkeeping); a stream message costs some more
  const std::size_t want = bytes + bytes / 2 + (64u << 10);
  if (want <= std::size_t(size) / 2) return;
  const int ask = static_cast<int>(std::min<std::size_t>(want, 1u << 30));
  ::setsockopt(sock, SOL_SOCKET, SO_SNDBUF, &ask, sizeof ask);
}

/// The parts of a message still to transfer: a copy of the caller's (at most kMax), with the
/// transferred bytes dropped from the front.
class Parts {
 public:
  static constexpr int kMax = 8;
  Parts(const iovec* parts, int count) {
    // empty parts are dropped: a part of no bytes left would look like the end of the message
    for (int k = 0; k < count; ++k)
      if (parts[k].iov_len > 0) {
        if (m_count == kMax) throw std::logic_error("external engine: a message of too many parts");
        m_parts[m_count++] = parts[k];
      }
  }
  bool empty() const { return m_first == m_count; }
  iovec* data() { return m_parts + m_first; }
  int size() const { return m_count - m_first; }
  /// Drops n transferred bytes from the front.
  void consume(std::size_t n) {
    while (n > 0 && !empty()) {
      iovec& p = m_parts[m_first];
      const std::size_t k = std::min(n, p.iov_len);
      p.iov_base = static_cast<char*>(p.iov_base) + k;
      p.iov_len -= k;
      n -= k;
      if (p.iov_len == 0) ++m_first;
    }
  }

 private:
  iovec m_parts[kMax];
  int m_first = 0, m_count = 0;
};

}  // namespace

ExternalProcess::ExternalProcess(const std::vector<std::string>& command,
                                 std::size_t message_bytes) {
  if (command.empty()) throw cloth::EngineFailure("external engine: an empty command");
  m_name = command.front();
  std::vector<std::string> args = command;
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // close-on-exec everywhere: a sibling engine started by another thread must not inherit ours
  int sv[2], err[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0)
    throw cloth::EngineFailure(std::string("external engine: socketpair: ") + std::strerror(errno));
  if (::pipe2(err, O_CLOEXEC) != 0) {
    ::close(sv[0]);
    ::close(sv[1]);
    throw cloth::EngineFailure(std::string("external engine: pipe: ") + std::strerror(errno));
  }
  m_socket = sv[0];
  m_stderr_fd = err[0];
  make_room(sv[0], message_bytes);
  make_room(sv[1], message_bytes);
  const int e = spawn(argv.data(), sv[1], err[1]);
  ::close(sv[1]);
  ::close(err[1]);
  if (e != 0) {
    close_fd(m_socket);
    close_fd(m_stderr_fd);
    throw cloth::EngineFailure("external engine: cannot run " + m_name + ": " + std::strerror(e));
  }
  ::fcntl(m_stderr_fd, F_SETFL, O_NONBLOCK);
}

int ExternalProcess::spawn(char* const* argv, int sock, int err) {
  // the child's stdin and stdout the socket, its stderr the pipe (dup2 clears close-on-exec),
  // SIGPIPE back to its default and no signal blocked, whatever this thread has
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attributes;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, sock, 0);
  posix_spawn_file_actions_adddup2(&actions, sock, 1);
  posix_spawn_file_actions_adddup2(&actions, err, 2);
  posix_spawnattr_init(&attributes);
  sigset_t none, pipe;
  sigemptyset(&none);
  sigemptyset(&pipe);
  sigaddset(&pipe, SIGPIPE);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &pipe);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  // a program that cannot be run is an error here (glibc reports a failed exec), not an exit
  pid_t pid = 0;
  const int e = ::posix_spawnp(&pid, argv[0], &actions, &attributes, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (e == 0) m_pid = pid;
  return e;
}

ExternalProcess::~ExternalProcess() {
  // end of input asks the engine to exit; it has a moment before it is killed
  if (m_socket >= 0) ::shutdown(m_socket, SHUT_WR);
  if (m_pid > 0) reap(std::chrono::milliseconds(2000));
  close_fd(m_socket);
  close_fd(m_stderr_fd);
}

bool ExternalProcess::drain_stderr() {
  char buf[4096];
  for (;;) {
    const ssize_t n = m_stderr_fd < 0 ? 0 : ::read(m_stderr_fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 && errno == EAGAIN;
    m_stderr.append(buf, static_cast<size_t>(n));
    if (m_stderr.size() > kStderrTail) m_stderr.erase(0, m_stderr.size() - kStderrTail);
  }
}

void ExternalProcess::wait_for(short events, Clock::time_point deadline) {
  for (;;) {
    pollfd fds[2] = {{m_socket, events, 0}, {m_stderr_fd, POLLIN, 0}};
    const int r = ::poll(fds, m_stderr_fd >= 0 ? 2 : 1, ms_left(deadline));
    if (r < 0 && errno == EINTR) continue;
    if (fds[1].revents != 0 && !drain_stderr()) close_fd(m_stderr_fd);
    if (fds[0].revents != 0) return;
    if (Clock::now() >= deadline) fail("no answer within its step_timeout");
  }
}

void ExternalProcess::write(const void* data, std::size_t n, Clock::time_point deadline) {
  const iovec part{const_cast<void*>(data), n};
  write(&part, 1, deadline);
}

void ExternalProcess::write(const iovec* parts, int count, Clock::time_point deadline) {
  Parts left(parts, count);
  while (!left.empty()) {
    // try first: a request fits the socket's buffer, so poll only when it is full
    msghdr m{};
    m.msg_iov = left.data();
    m.msg_iovlen = static_cast<std::size_t>(left.size());
    const ssize_t w = ::sendmsg(m_socket, &m, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (w < 0 && errno == EAGAIN) wait_for(POLLOUT, deadline);
    if (w < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (w < 0) fail("stopped reading its input (" + std::string(std::strerror(errno)) + ")");
    left.consume(static_cast<std::size_t>(w));
  }
}

void ExternalProcess::read(void* data, std::size_t n, Clock::time_point deadline) {
  const iovec part{data, n};
  read(&part, 1, deadline);
}

void ExternalProcess::read(const iovec* parts, int count, Clock::time_point deadline) {
  Parts left(parts, count);
  while (!left.empty()) {
    // try first: the rest of an answer has usually arrived with its header
    msghdr m{};
    m.msg_iov = left.data();
    m.msg_iovlen = static_cast<std::size_t>(left.size());
    const ssize_t r = ::recvmsg(m_socket, &m, MSG_DONTWAIT);
    if (r < 0 && errno == EAGAIN) wait_for(POLLIN, deadline);
    if (r < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (r == 0) fail("closed its output before the end of an answer");
    if (r < 0) fail("cannot be read (" + std::string(std::strerror(errno)) + ")");
    left.consume(static_cast<std::size_t>(r));
  }
}

std::string ExternalProcess::reap(std::chrono::milliseconds grace) {
  if (m_pid <= 0) return m_ended;
  const auto until = Clock::now() + grace;
  int status = 0;
  pid_t r = 0;
  // a short poll for a clean exit, then the kill
  while ((r = ::waitpid(m_pid, &status, WNOHANG)) == 0 && Clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  if (r == 0) {
    ::kill(m_pid, SIGKILL);
    while ((r = ::waitpid(m_pid, &status, 0)) < 0 && errno == EINTR) {
    }
    m_ended = "killed by the harness";
  } else if (r > 0 && WIFEXITED(status)) {
    m_ended = "exited with status " + std::to_string(WEXITSTATUS(status));
  } else if (r > 0 && WIFSIGNALED(status)) {
    m_ended = "killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
              strsignal(WTERMSIG(status)) + ")";
  }
  m_pid = 0;
  return m_ended;
}

void ExternalProcess::fail(const std::string& why) {
  // an engine that is dying gets a moment to finish its stderr and exit on its own
  const std::string ended = reap(std::chrono::milliseconds(200));
  for (int k = 0; k < 50 && m_stderr_fd >= 0; ++k) {
    pollfd fd{m_stderr_fd, POLLIN, 0};
    if (::poll(&fd, 1, 10) <= 0) break;
    if (!drain_stderr()) close_fd(m_stderr_fd);
  }
  close_fd(m_socket);
  std::string tail = m_stderr;
  for (char& c : tail)
    if (c == '\n' || c == '\r' || c == '"' || c == '\\') c = c == '"' ? '\'' : ' ';
  while (!tail.empty() && tail.back() == ' ') tail.pop_back();
  const size_t keep = 300;
  if (tail.size() > keep) tail = "..." + tail.substr(tail.size() - keep);
  throw cloth::EngineFailure("external engine " + m_name + " " + why + " (" + ended + ")" +
                             (tail.empty() ? "" : "; its stderr ends: " + tail));
}

}  // namespace clothbench::reference
