#include "joints/input_file.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <vector>

#include "joints/resource_limits.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {

bool readInputFile(const std::string& path, std::uint64_t max_bytes, std::string* text) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return false;
  std::string out;
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec)) {
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && size > max_bytes)
      throw limitExceeded(path, "bytes (the file's size)", static_cast<double>(size), static_cast<double>(max_bytes),
                          "--max-input-mb");
    if (!ec) out.reserve(size);
  }
  std::vector<char> buffer(1 << 16);
  while (out.size() <= max_bytes) {
    const std::uint64_t room = max_bytes + 1 - out.size();
    file.read(buffer.data(), static_cast<std::streamsize>(std::min<std::uint64_t>(buffer.size(), room)));
    // Scenes, models and recordings are text: a NUL byte means a binary file
    // or a device such as /dev/zero, refused at once instead of at the limit.
    const std::size_t got = static_cast<std::size_t>(file.gcount());
    if (const void* nul = std::memchr(buffer.data(), '\0', got))
      throw InvalidInput(path, "holds a NUL byte at offset " +
                                   std::to_string(out.size() + static_cast<std::size_t>(
                                                                   static_cast<const char*>(nul) - buffer.data())) +
                                   ": not a text file (scenes, models and recordings are text)");
    out.append(buffer.data(), got);
    if (file.gcount() == 0 || !file) break;
  }
  if (out.size() > max_bytes)
    throw limitExceeded(path, "bytes read (the file is larger, or an endless stream)", static_cast<double>(out.size()),
                        static_cast<double>(max_bytes), "--max-input-mb");
  if (file.bad()) throw InvalidInput(path, "read error (is it a directory?)");
  *text = std::move(out);
  return true;
}

}  // namespace lieflow
