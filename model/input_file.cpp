#include "model/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include "model/resource_limits.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {

namespace {

/// A file descriptor closed when it goes.
struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

bool readInputFile(const std::string& path, std::uint64_t max_bytes, std::string* text) {
  // Opened without blocking: a FIFO that no program writes to would block a
  // plain open for ever; opened so, it reads as empty (and is refused as
  // such). Reads then block as usual, for a pipe that is being written.
  Descriptor file;
  file.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (file.fd < 0) return false;
  struct stat st;
  if (::fstat(file.fd, &st) != 0) return false;
  if (S_ISDIR(st.st_mode)) throw InvalidInput(path, "is a directory, not a file");
  const int flags = ::fcntl(file.fd, F_GETFL);
  if (flags >= 0) ::fcntl(file.fd, F_SETFL, flags & ~O_NONBLOCK);
  std::string out;
  if (S_ISREG(st.st_mode)) {
    const std::uint64_t size = static_cast<std::uint64_t>(st.st_size);
    if (size > max_bytes)
      throw limitExceeded(path, "bytes (the file's size)", static_cast<double>(size), static_cast<double>(max_bytes),
                          "`max_input_mb`");
    out.reserve(size);
  }
  std::vector<char> buffer(1 << 16);
  while (out.size() <= max_bytes) {
    const std::uint64_t room = max_bytes + 1 - out.size();
    const ssize_t got = ::read(file.fd, buffer.data(), std::min<std::uint64_t>(buffer.size(), room));
    if (got < 0) {
      if (errno == EINTR) continue;
      throw InvalidInput(path, std::string("read error: ") + std::strerror(errno));
    }
    if (got == 0) break;
    // Scenes, models and recordings are text: a NUL byte means a binary file
    // or a device such as /dev/zero, refused at once instead of at the limit.
    if (const void* nul = std::memchr(buffer.data(), '\0', static_cast<std::size_t>(got)))
      throw InvalidInput(path, "holds a NUL byte at offset " +
                                   std::to_string(out.size() + static_cast<std::size_t>(
                                                                   static_cast<const char*>(nul) - buffer.data())) +
                                   ": not a text file (scenes, models and recordings are text)");
    out.append(buffer.data(), static_cast<std::size_t>(got));
  }
  if (out.size() > max_bytes)
    throw limitExceeded(path, "bytes read (the file is larger, or an endless stream)", static_cast<double>(out.size()),
                        static_cast<double>(max_bytes), "`max_input_mb`");
  *text = std::move(out);
  return true;
}

}  // namespace lieflow
