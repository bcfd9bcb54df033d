#include "reference/external/external_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <thread>

#include "cloth/model/simulator.hpp"

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

/// The child's side after fork: its stdin and stdout the socket, stderr the pipe, then exec;
/// only async-signal-safe calls, and errno to the status pipe when exec fails.
[[noreturn]] void exec_child(char* const* argv, int sock, int err, int status) {
  if (::dup2(sock, 0) < 0 || ::dup2(sock, 1) < 0 || ::dup2(err, 2) < 0) _exit(127);
  ::signal(SIGPIPE, SIG_DFL);
  ::execvp(argv[0], argv);
  const int e = errno;
  [[maybe_unused]] const ssize_t n = ::write(status, &e, sizeof e);
  _exit(127);
}

}  // namespace

ExternalProcess::ExternalProcess(const std::vector<std::string>& command) {
  if (command.empty()) throw cloth::EngineFailure("external engine: an empty command");
  m_name = command.front();
  // argv before fork: the child may call nothing that allocates
  std::vector<std::string> args = command;
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // close-on-exec everywhere: a sibling engine started by another thread must not inherit ours
  int sv[2], err[2], status[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0)
    throw cloth::EngineFailure(std::string("external engine: socketpair: ") + std::strerror(errno));
  if (::pipe2(err, O_CLOEXEC) != 0 || ::pipe2(status, O_CLOEXEC) != 0)
    throw cloth::EngineFailure(std::string("external engine: pipe: ") + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid == 0) exec_child(argv.data(), sv[1], err[1], status[1]);
  ::close(sv[1]);
  ::close(err[1]);
  ::close(status[1]);
  m_socket = sv[0];
  m_stderr_fd = err[0];
  if (pid < 0) {
    close_fd(m_socket);
    close_fd(m_stderr_fd);
    ::close(status[0]);
    throw cloth::EngineFailure(std::string("external engine: fork: ") + std::strerror(errno));
  }
  m_pid = pid;
  // exec succeeded when the status pipe closes without a word
  int e = 0;
  ssize_t n;
  do n = ::read(status[0], &e, sizeof e);
  while (n < 0 && errno == EINTR);
  ::close(status[0]);
  if (n == sizeof e) {
    reap(std::chrono::milliseconds(0));
    close_fd(m_socket);
    close_fd(m_stderr_fd);
    throw cloth::EngineFailure("external engine: cannot run " + m_name + ": " + std::strerror(e));
  }
  ::fcntl(m_stderr_fd, F_SETFL, O_NONBLOCK);
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
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    wait_for(POLLOUT, deadline);
    const ssize_t w = ::send(m_socket, p, n, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (w < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (w < 0) fail("stopped reading its input (" + std::string(std::strerror(errno)) + ")");
    p += w;
    n -= static_cast<std::size_t>(w);
  }
}

void ExternalProcess::read(void* data, std::size_t n, Clock::time_point deadline) {
  char* p = static_cast<char*>(data);
  while (n > 0) {
    wait_for(POLLIN, deadline);
    const ssize_t r = ::recv(m_socket, p, n, MSG_DONTWAIT);
    if (r < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (r == 0) fail("closed its output before the end of an answer");
    if (r < 0) fail("cannot be read (" + std::string(std::strerror(errno)) + ")");
    p += r;
    n -= static_cast<std::size_t>(r);
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
