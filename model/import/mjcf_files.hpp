/// \file
/// An MJCF model's files checked before MuJoCo's compiler sees them
/// (mjcf_import.cpp). The compiler reads `<include>`d files and assets
/// itself and its cost grows faster than the model (the body count is known
/// only after it ran), so what it would spend is bounded first, from the
/// files: their total size against --max-input-mb (the model file, every
/// included file and every mesh, height field, texture and skin file it
/// names), the bodies they declare against --max-bodies, and every number
/// they hold (XmlLines::requireUsableNumbers), named by file, element, line
/// and attribute.
#pragma once

#include <cstdint>
#include <string>

#include "model/resource_limits.hpp"

namespace lieflow {
namespace model_import {

/// What checkMjcfFiles found.
struct MjcfFiles {
  int files = 0;             ///< the model file and the files it includes
  std::uint64_t bytes = 0;   ///< their size and that of the assets they name
  long declared_bodies = 0;  ///< <body> elements, and the bodies <composite> elements make
};

/// Checks the model file `path` (contents `text`) and everything it
/// includes or names as above. Throws InvalidInput naming the file, the
/// element and its line: broken XML, an unreadable include, a file that is
/// not a regular one, a bad number, a limit exceeded (with the option that
/// raises it).
MjcfFiles checkMjcfFiles(const std::string& path, const std::string& text, const ResourceLimits& limits);

}  // namespace model_import
}  // namespace lieflow
