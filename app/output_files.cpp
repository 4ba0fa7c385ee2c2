#include "app/output_files.hpp"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace app {

namespace {

/// Most links followed from an output path to the file it names (the
/// kernel's own limit, ELOOP, is 40).
constexpr int kMaxSymlinks = 40;

/// The file `path` names, its symbolic links followed (also a link to a file
/// that does not exist yet), so that the finished file replaces the target
/// and not the link.
std::filesystem::path linkTarget(const std::string& option, const std::string& path) {
  std::filesystem::path p(path);
  std::error_code ec;
  for (int k = 0; std::filesystem::is_symlink(p, ec); ++k) {
    if (k == kMaxSymlinks) throw InvalidInput(option + " " + path, "too many levels of symbolic links");
    const std::filesystem::path next = std::filesystem::read_symlink(p, ec);
    if (ec) throw InvalidInput(option + " " + path, "cannot read the symbolic link: " + ec.message());
    p = next.is_absolute() ? next : p.parent_path() / next;
  }
  return p;
}

}  // namespace

AtomicOutputFile::AtomicOutputFile(const std::string& path, const std::string& option) : path_(path) {
  if (path.empty()) throw InvalidInput(option, "empty file name (omit the option to write to standard output)");
  const std::filesystem::path target = linkTarget(option, path);
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(target, ec);
  if (std::filesystem::is_directory(status)) throw InvalidInput(option + " " + path, "is a directory");
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    // A device or a pipe (/dev/null, a FIFO a program reads): written
    // directly; it cannot be replaced by a renamed file, and must not be.
    direct_ = true;
    file_.open(target, std::ios::out);
    if (!file_) throw InvalidInput(option + " " + path, "cannot open it for writing");
    return;
  }
  target_ = target.string();
  partial_ = target_ + ".partial";
  file_.open(partial_, std::ios::out | std::ios::trunc);
  if (!file_) throw InvalidInput(option + " " + path, "cannot open " + partial_ + " for writing");
}

AtomicOutputFile::~AtomicOutputFile() {
  if (!done_) abandon();
}

void AtomicOutputFile::commit() {
  file_.close();
  done_ = true;
  if (!file_) {
    if (!direct_) std::remove(partial_.c_str());
    throw InvalidInput(path_, "write failed (disk full or file system error)");
  }
  if (direct_) return;
  std::error_code ec;
  std::filesystem::rename(partial_, target_, ec);
  if (ec) throw InvalidInput(path_, "cannot rename " + partial_ + " to " + target_ + ": " + ec.message());
}

std::string AtomicOutputFile::abandon() {
  if (done_) return "";
  done_ = true;
  if (direct_) {
    file_.close();
    return "";
  }
  const bool any = file_.tellp() > 0;
  file_.close();
  if (!any) {
    std::remove(partial_.c_str());
    return "";
  }
  return "the rows written before the failure are in " + partial_ + " (" + path_ + " was not written)";
}

OutputDirectory::OutputDirectory(const std::string& dir) {
  if (dir.empty()) throw InvalidInput("--out", "empty directory name");
  std::error_code ec;
  // The directories that do not exist yet, deepest first: the ones to remove
  // again if nothing is written.
  for (std::filesystem::path p = std::filesystem::absolute(dir, ec).lexically_normal();
       !p.empty() && !std::filesystem::exists(p, ec) && p != p.parent_path(); p = p.parent_path())
    created_.push_back(p.string());
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InvalidInput("--out " + dir, "cannot create the directory: " + ec.message());
  if (!std::filesystem::is_directory(dir, ec)) throw InvalidInput("--out " + dir, "exists and is not a directory");
  const std::string probe = dir + "/.lieflow-write-probe";
  std::FILE* f = std::fopen(probe.c_str(), "w");
  if (!f) throw InvalidInput("--out " + dir, "the directory is not writable");
  std::fclose(f);
  std::remove(probe.c_str());
}

OutputDirectory::~OutputDirectory() {
  if (kept_) return;
  std::error_code ec;
  for (const std::string& d : created_)
    if (std::filesystem::is_empty(d, ec) && !ec) std::filesystem::remove(d, ec);
}

}  // namespace app
}  // namespace lieflow
