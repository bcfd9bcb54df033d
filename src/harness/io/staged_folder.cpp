#include "harness/io/staged_folder.hpp"

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

#include "harness/io/csv_writer.hpp"
#include "harness/io/user_error.hpp"

namespace clothbench {

namespace fs = std::filesystem;

namespace {

/// The folder without a trailing separator, so that its name and parent are well defined.
fs::path normalised(const std::string& dir) {
  fs::path p = fs::absolute(fs::path(dir)).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p;
}

/// The prefix of every stage of the folder: .<name>.clothbench-new-
std::string stage_prefix(const fs::path& dir) {
  return "." + dir.filename().string() + ".clothbench-new-";
}

/// Removes stages of dir left by commands that were killed before their commit: beside the
/// folder, or inside it when its parent was not writable.
void remove_leftover_stages(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> stale;
  const std::string prefix = stage_prefix(dir);
  for (const auto& e : fs::directory_iterator(dir.parent_path(), ec))
    if (e.path().filename().string().rfind(prefix, 0) == 0) stale.push_back(e.path());
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().filename().string().rfind(".clothbench-new-", 0) == 0) stale.push_back(e.path());
  for (const fs::path& p : stale) fs::remove_all(p, ec);
}

/// Makes name in dir also reachable in stage: a hard link for a file, a rename otherwise.
void carry_over(const fs::path& entry, const fs::path& stage) {
  const fs::path target = stage / entry.filename();
  std::error_code ec;
  if (fs::exists(fs::symlink_status(target, ec))) return;  // the stage replaces it
  if (fs::is_regular_file(fs::symlink_status(entry, ec)) &&
      ::link(entry.c_str(), target.c_str()) == 0)
    return;
  fs::rename(entry, target, ec);
  if (ec)
    throw UserError("cannot carry " + entry.string() + " over to the new run: " + ec.message());
}

/// Renames every staged entry into dir, one by one (a file system without RENAME_EXCHANGE).
void move_in_one_by_one(const fs::path& stage, const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(stage)) {
    std::error_code ec;
    fs::rename(e.path(), dir / e.path().filename(), ec);
    if (ec)
      throw UserError("cannot move " + e.path().string() + " into " + dir.string() + ": " +
                      ec.message());
  }
}

}  // namespace

StagedFolder::StagedFolder(const std::string& dir) {
  const fs::path d = normalised(dir);
  m_dir = d.string();
  remove_leftover_stages(d);
  m_stage = (d.parent_path() / (stage_prefix(d) + std::to_string(::getpid()))).string();
  std::error_code ec;
  if (fs::create_directory(m_stage, ec) && !ec) return;
  // a folder whose parent is not writable: stage inside it, and move in one by one
  m_inside = true;
  m_stage = m_dir + "/.clothbench-new-" + std::to_string(::getpid());
  fs::remove_all(m_stage, ec);
  make_directories(m_stage);
}

StagedFolder::~StagedFolder() {
  if (m_committed) return;
  std::error_code ec;
  fs::remove_all(m_stage, ec);
}

std::string StagedFolder::in_folder(std::string message) const {
  const std::string stage = m_stage + "/", dir = m_dir + "/";
  for (size_t at = message.find(stage); at != std::string::npos; at = message.find(stage, at))
    message.replace(at, stage.size(), dir), at += dir.size();
  return message;
}

void StagedFolder::commit() {
  const fs::path dir(m_dir), stage(m_stage);
  if (m_inside) {
    std::error_code ec;
    for (const std::string& name : m_owned) fs::remove_all(dir / name, ec);
    move_in_one_by_one(stage, dir);
  } else {
    swap_in(dir, stage);
  }
  m_committed = true;
  std::error_code ec;
  fs::remove_all(stage, ec);  // the old run (or, after one-by-one moves, an empty folder)
}

void StagedFolder::swap_in(const fs::path& dir, const fs::path& stage) {
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (std::find(m_owned.begin(), m_owned.end(), name) == m_owned.end())
      carry_over(e.path(), stage);
  }
  if (::renameat2(AT_FDCWD, stage.c_str(), AT_FDCWD, dir.c_str(), RENAME_EXCHANGE) != 0) {
    if (errno != EINVAL && errno != ENOSYS)
      throw UserError("cannot put the new run in place of " + dir.string() + ": " +
                      std::strerror(errno));
    move_in_one_by_one(stage, dir);
  }
}

}  // namespace clothbench
