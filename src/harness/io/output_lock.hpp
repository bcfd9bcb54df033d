#pragma once
/// @file output_lock.hpp
/// An output folder held by one command at a time: DIR/.clothbench.lock, locked with flock
/// while the command runs (the kernel drops the lock when the process ends, however it ends),
/// so that two commands never mix their files in one folder.

#include <string>

namespace clothbench {

/// The name of the lock file in an output folder.
extern const char* const kLockFileName;

/// Holds the lock of an output folder for its lifetime.
class OutputLock {
 public:
  /// Creates dir (and its parents) when missing and locks it. Throws UserError naming the
  /// folder and the command that holds it (its pid and command line) when another one does,
  /// or when the folder cannot be created or written.
  explicit OutputLock(const std::string& dir);
  /// Unlocks; removes the lock file, and the folder when this lock created it and nothing
  /// else was written there (a command that fails leaves no folder behind).
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  std::string m_dir, m_path;
  int m_fd = -1;
  bool m_created = false;  // the folder did not exist before
};

}  // namespace clothbench
