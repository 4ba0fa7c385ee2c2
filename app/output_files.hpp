/// \file
/// Output files of the `lieflow` commands, checked before the work starts and
/// never left looking complete when the work failed:
/// - `AtomicOutputFile` writes FILE.partial beside FILE and renames it to FILE
///   only on success (`commit`); a failed run leaves FILE as it was and its
///   rows in FILE.partial, and says so (`abandon`). A symbolic link is
///   followed (its target is replaced, not the link); a device or pipe
///   (/dev/null, a FIFO) is written directly, never replaced.
/// - `OutputDirectory` creates an --out directory and proves it writable
///   before a study or stability scan spends minutes computing, and removes
///   it again when the command was refused before writing anything.
#pragma once

#include <fstream>
#include <string>
#include <vector>

namespace lieflow {
namespace app {

class AtomicOutputFile {
 public:
  /// Opens PATH.partial for writing; InvalidInput naming `option` and PATH
  /// when PATH is empty or cannot be written.
  AtomicOutputFile(const std::string& path, const std::string& option);
  ~AtomicOutputFile();
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

  std::ostream& stream() { return file_; }
  const std::string& path() const { return path_; }

  /// Flushes, closes and renames PATH.partial to PATH (throws when the
  /// write or the rename failed: a full disk is found here, not later).
  void commit();
  /// After a failure: closes PATH.partial and returns a sentence for the
  /// error message saying where the rows written so far are ("" if none).
  std::string abandon();

 private:
  std::string path_;     ///< as given (for messages)
  std::string target_;   ///< the file it names, symbolic links followed
  std::string partial_;  ///< target_ + ".partial"
  std::ofstream file_;
  bool direct_ = false;  ///< a device or pipe, written in place
  bool done_ = false;
};

/// An --out directory for the run of a command: created (with its parents)
/// and proved writable (a probe file written and removed) before the work
/// starts, InvalidInput("--out DIR", why) when that fails or DIR is empty.
/// A run refused or failed before it wrote anything leaves nothing behind:
/// unless `keep()` was called, the directories this created are removed when
/// it goes, if they are still empty.
class OutputDirectory {
 public:
  explicit OutputDirectory(const std::string& dir);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;
  /// The work wrote its files: the directory stays.
  void keep() { kept_ = true; }

 private:
  std::vector<std::string> created_;  ///< deepest first
  bool kept_ = false;
};

}  // namespace app
}  // namespace lieflow
