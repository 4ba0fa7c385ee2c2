/// \file
/// Reading an input file (scene or recording) whole, within the size limit
/// of model/resource_limits.hpp: a regular file is checked by its size
/// before anything is read; a stream that never ends (/dev/zero, a FIFO) is
/// read to one byte past the limit and refused there, instead of filling the
/// memory.
#pragma once

#include <cstdint>
#include <string>

namespace lieflow {

/// The contents of `path`; false (and `text` untouched) if it cannot be
/// opened. Throws InvalidInput naming `path`, the limit and --max-input-mb
/// past `max_bytes`, naming `path` on a read error (a directory), and at
/// the first NUL byte (not text: a binary file, /dev/zero).
bool readInputFile(const std::string& path, std::uint64_t max_bytes, std::string* text);

}  // namespace lieflow
