#include "app/output_files.hpp"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace app {

AtomicOutputFile::AtomicOutputFile(const std::string& path, const std::string& option)
    : path_(path), partial_(path + ".partial") {
  if (path.empty()) throw InvalidInput(option, "empty file name (omit the option to write to standard output)");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InvalidInput(option + " " + path, "is a directory");
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
    std::remove(partial_.c_str());
    throw InvalidInput(path_, "write failed (disk full or file system error)");
  }
  std::error_code ec;
  std::filesystem::rename(partial_, path_, ec);
  if (ec) throw InvalidInput(path_, "cannot rename " + partial_ + " to it: " + ec.message());
}

std::string AtomicOutputFile::abandon() {
  if (done_) return "";
  done_ = true;
  const bool any = file_.tellp() > 0;
  file_.close();
  if (!any) {
    std::remove(partial_.c_str());
    return "";
  }
  return "the rows written before the failure are in " + partial_ + " (" + path_ + " was not written)";
}

void prepareOutputDirectory(const std::string& dir) {
  if (dir.empty()) throw InvalidInput("--out", "empty directory name");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InvalidInput("--out " + dir, "cannot create the directory: " + ec.message());
  if (!std::filesystem::is_directory(dir, ec)) throw InvalidInput("--out " + dir, "exists and is not a directory");
  const std::string probe = dir + "/.lieflow-write-probe";
  std::FILE* f = std::fopen(probe.c_str(), "w");
  if (!f) throw InvalidInput("--out " + dir, "the directory is not writable");
  std::fclose(f);
  std::remove(probe.c_str());
}

}  // namespace app
}  // namespace lieflow
