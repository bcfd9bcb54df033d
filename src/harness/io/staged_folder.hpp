#pragma once
/// @file staged_folder.hpp
/// A run's files written into a hidden sibling of the output folder and swapped in with one
/// rename, so that a reader (or a crash) never sees the new frames.csv beside the old
/// summary.csv: either every file of the old run is there or every file of the new one.

#include <filesystem>
#include <string>
#include <vector>

namespace clothbench {

/// A hidden sibling of an output folder, <parent>/.<name>.clothbench-new-<pid>, that takes
/// the place of the folder on commit(). The caller holds the folder's OutputLock.
class StagedFolder {
 public:
  /// Removes the leftovers of earlier commands killed before their commit (only the holder
  /// of the folder's lock stages into it) and creates the sibling. Throws UserError naming
  /// the folder when it cannot be created.
  explicit StagedFolder(const std::string& dir);
  /// Removes the sibling when commit() was not reached (an error or an interrupt).
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  /// Where to write: the sibling folder, with a trailing '/'.
  std::string path() const { return m_stage + "/"; }

  /// Makes the old folder's entry name go with the old run instead of being carried over: an
  /// output the run owns whole (written or not this time), such as its trajectory folder.
  void owns(const std::string& name) { m_owned.push_back(name); }

  /// A message about a staged file, naming the file where it will be in the folder instead
  /// (a user knows the folder, not the stage).
  std::string in_folder(std::string message) const;

  /// Carries every entry of the folder that the stage does not replace into the stage (files
  /// as hard links, so that they never leave the folder; folders by rename), then swaps the
  /// two folders in one rename (Linux renameat2 RENAME_EXCHANGE) and removes the old one.
  /// Where the file system cannot swap, or the folder's parent is not writable (the stage is
  /// then a hidden folder inside it), the staged files are renamed in one by one.
  void commit();

 private:
  void swap_in(const std::filesystem::path& dir, const std::filesystem::path& stage);

  std::string m_dir, m_stage;
  std::vector<std::string> m_owned;  // entries of the folder the run replaces whole
  bool m_inside = false;             // the stage is inside the folder
  bool m_committed = false;
};

}  // namespace clothbench
