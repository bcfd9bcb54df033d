#include "harness/io/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "harness/io/csv_writer.hpp"
#include "harness/io/text_file.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench {

const char* const kLockFileName = ".clothbench.lock";

namespace {

/// "pid N: the command line" of this process, for the message of a second command.
std::string holder_text() {
  std::string cmdline = read_text("/proc/self/cmdline");
  for (char& c : cmdline)
    if (c == '\0') c = ' ';
  while (!cmdline.empty() && cmdline.back() == ' ') cmdline.pop_back();
  return "pid " + std::to_string(::getpid()) + ": " + cmdline + "\n";
}

/// True when fd is still the file at path (a lock on a file unlinked by its previous holder
/// guards nothing).
bool same_file(int fd, const std::string& path) {
  struct stat a {
  }, b{};
  return ::fstat(fd, &a) == 0 && ::stat(path.c_str(), &b) == 0 && a.st_ino == b.st_ino &&
         a.st_dev == b.st_dev;
}

}  // namespace

OutputLock::OutputLock(const std::string& dir) : m_dir(dir), m_path(dir + "/" + kLockFileName) {
  std::error_code ec;
  m_created = !std::filesystem::exists(dir, ec) && !ec;
  make_directories(dir);
  for (int attempt = 0; attempt < 10; ++attempt) {
    m_fd = ::open(m_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (m_fd < 0)
      throw UserError("cannot write in output folder " + dir + ": " + std::strerror(errno));
    if (::flock(m_fd, LOCK_EX | LOCK_NB) != 0) {
      std::string holder = read_text(m_path);
      while (!holder.empty() && holder.back() == '\n') holder.pop_back();
      ::close(m_fd);
      throw UserError("output folder " + dir + " is in use by another clothbench command (" +
                      (holder.empty() ? std::string("unknown") : holder) +
                      "); wait for it to end or choose another output folder");
    }
    if (same_file(m_fd, m_path)) break;
    ::close(m_fd);  // its holder removed it as we opened it: lock the new one
    m_fd = -1;
  }
  if (m_fd < 0) throw UserError("cannot lock output folder " + dir);
  // who holds it, for the message of a second command: best effort (the lock is the flock,
  // and a full disk is for the command's own files to report)
  const std::string text = holder_text();
  const bool written =
      ::ftruncate(m_fd, 0) == 0 && ::write(m_fd, text.data(), text.size()) == ssize_t(text.size());
  (void)written;
}

OutputLock::~OutputLock() {
  if (m_fd < 0) return;
  ::unlink(m_path.c_str());
  ::close(m_fd);
  std::error_code ec;
  if (m_created && std::filesystem::is_empty(m_dir, ec) && !ec) std::filesystem::remove(m_dir, ec);
}

}  // namespace clothbench
