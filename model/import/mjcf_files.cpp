// An MJCF model's files, checked before MuJoCo compiles them: mjcf_files.hpp.
#ifdef LIEFLOW_HAVE_MUJOCO
#include "model/import/mjcf_files.hpp"

#include <sys/stat.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include "model/import/xml_lines.hpp"
#include "model/input_file.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace model_import {

namespace {

/// MJCF attributes that hold names, references, file names or keywords:
/// never read as numbers, even when a name looks like one.
const std::vector<std::string>& mjcfTextAttributes() {
  static const std::vector<std::string> kText = {
      "name", "class", "childclass", "model", "file", "meshdir", "texturedir", "joint", "joint1", "joint2",
      "body", "body1", "body2", "site", "site1", "site2", "geom", "geom1", "geom2", "tendon", "tendon1",
      "tendon2", "actuator", "mesh", "material", "texture", "hfield", "skin", "objname", "refname", "prefix",
      "target", "slidersite", "cranksite", "jointinparent", "fileright", "fileleft", "fileup", "filedown",
      "filefront", "fileback", "content_type", "type", "objtype", "reftype", "key"};
  return kText;
}

/// The largest sizes an MJCF may ask MuJoCo to allocate, checked before it
/// does (beyond, mj_makeData ran out of memory or threw std::bad_alloc):
/// counts of <size> (8 bytes or more each: nstack 10⁸ is 800 MB), keyframes
/// (each holds qpos, qvel, act), user data per element, and the texels and
/// height-field samples of generated textures and height fields.
struct SizeLimit {
  const char* tag;
  const char* attribute;
  double most;
};
constexpr SizeLimit kSizeLimits[] = {
    {"size", "nstack", 1e8},       {"size", "nuserdata", 1e8},    {"size", "njmax", 1e7},
    {"size", "nconmax", 1e7},      {"size", "nkey", 1e5},         {"size", "memory", 1e10},
    {"size", "nuser_body", 1e3},   {"size", "nuser_jnt", 1e3},    {"size", "nuser_geom", 1e3},
    {"size", "nuser_site", 1e3},   {"size", "nuser_cam", 1e3},    {"size", "nuser_tendon", 1e3},
    {"size", "nuser_actuator", 1e3}, {"size", "nuser_sensor", 1e3}, {"texture", "width", 1e4},
    {"texture", "height", 1e4},    {"hfield", "nrow", 1e4},       {"hfield", "ncol", 1e4},
};

/// Below this norm a `quat` attribute is refused.
constexpr double kMinQuaternionNorm = 1e-6;

/// Asset elements and the attributes that name their files.
bool isAssetFileAttribute(const std::string& tag, const std::string& attribute) {
  if (tag == "texture")
    return attribute == "file" || attribute == "fileright" || attribute == "fileleft" || attribute == "fileup" ||
           attribute == "filedown" || attribute == "filefront" || attribute == "fileback";
  return (tag == "mesh" || tag == "hfield" || tag == "skin") && attribute == "file";
}

std::string directoryOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string joined(const std::string& dir, const std::string& file) {
  if (!file.empty() && file.front() == '/') return file;
  return dir + file;
}

/// Bodies a <composite> makes: the product of its counts (at least 1 each).
long compositeBodies(const tinyxml2::XMLElement* e) {
  constexpr double kMany = 1e12;  // more than any limit: saturates the count
  const char* count = e->Attribute("count");
  if (!count) return 1;
  double bodies = 1.0;
  std::istringstream s(count);
  double n = 0.0;
  while (s >> n)
    if (n >= 1.0) bodies *= n;
  return static_cast<long>(std::min(bodies, kMany));
}

}  // namespace

MjcfFiles checkMjcfFiles(const std::string& path, const std::string& text, const ResourceLimits& limits) {
  MjcfFiles out;
  const std::string model_dir = directoryOf(path);
  std::string meshdir, texturedir;
  std::set<std::string> seen{path};
  std::set<std::string> assets;
  struct File {
    std::string path, text, included_by;  ///< included_by: "model.xml: include (line 2)", or empty
  };
  std::deque<File> files{{path, text, ""}};
  out.bytes = text.size();
  const auto over_budget = [&](const std::string& where, std::uint64_t bytes) {
    return limitExceeded(where, "bytes of model files (this file and those it includes or names)",
                         static_cast<double>(out.bytes + bytes), static_cast<double>(limits.max_input_bytes),
                         "`max_input_mb`");
  };
  while (!files.empty()) {
    const File current = files.front();
    files.pop_front();
    const std::string& file = current.path;
    ++out.files;
    std::optional<XmlLines> parsed;
    try {
      parsed.emplace(current.text, file);
    } catch (const InvalidInput& e) {
      if (current.included_by.empty()) throw;
      throw InvalidInput(current.included_by, "the included file " + std::string(e.what()));
    }
    const XmlLines& xml = *parsed;
    xml.requireUsableNumbers(file, mjcfTextAttributes());
    for (const tinyxml2::XMLElement* e : xml.elements()) {
      const std::string tag = e->Name();
      if (tag == "body") ++out.declared_bodies;
      if (tag == "composite") out.declared_bodies += compositeBodies(e);
      if (tag == "compiler") {
        if (const char* d = e->Attribute("meshdir")) meshdir = d;
        if (const char* d = e->Attribute("texturedir")) texturedir = d;
      }
      const std::string where = file + ": " + XmlLines::label(e);
      for (const SizeLimit& limit : kSizeLimits) {
        if (tag != limit.tag) continue;
        const char* value = e->Attribute(limit.attribute);
        if (!value) continue;
        const double asked = std::strtod(value, nullptr);
        if (asked > limit.most)
          throw InvalidInput(where + ", attribute " + limit.attribute,
                             formatNumber(asked) + " is more than lieflow lets MuJoCo allocate (" +
                                 formatNumber(limit.most) + "); the model's data would not fit in memory");
      }
      if (const char* quat = e->Attribute("quat")) {
        // MuJoCo normalizes a quaternion; one of (near) zero norm would
        // silently become the identity.
        std::istringstream values(quat);
        double squared = 0.0, x = 0.0;
        while (values >> x) squared += x * x;
        if (!(std::sqrt(squared) >= kMinQuaternionNorm))
          throw InvalidInput(where + ", attribute quat", "has norm " + formatNumber(std::sqrt(squared)) +
                                                             ": a quaternion of (near) zero norm gives no orientation");
      }
      if (tag == "include") {
        const char* name = e->Attribute("file");
        if (!name) continue;  // MuJoCo's compiler names the missing attribute
        const std::string included = joined(model_dir, name);
        if (!seen.insert(included).second) continue;  // MuJoCo refuses a file included twice
        if (limits.max_input_bytes <= out.bytes) throw over_budget(where, 1);
        std::string t;
        try {
          if (!readInputFile(included, limits.max_input_bytes - out.bytes, &t))
            throw InvalidInput(where, "cannot open the included file '" + included + "'");
        } catch (const InvalidInput& e) {
          if (e.field() == where) throw;
          // Its size counts with the model file's: say so, naming the include.
          throw InvalidInput(where, "the included file " + std::string(e.what()) +
                                        (e.reason().find("`max_input_mb`") != std::string::npos
                                             ? " (the model's files together)"
                                             : ""));
        }
        out.bytes += t.size();
        files.push_back({included, std::move(t), where});
        continue;
      }
      for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
        if (!isAssetFileAttribute(tag, a->Name())) continue;
        // The asset where MuJoCo looks for it (the model's directory, with
        // the compiler's meshdir or texturedir), counted once.
        for (const std::string& dir : {meshdir, texturedir, std::string()}) {
          const std::string candidate = joined(joined(model_dir, dir.empty() || dir.back() == '/' ? dir : dir + "/"),
                                               a->Value());
          struct stat st;
          if (stat(candidate.c_str(), &st) != 0) continue;
          if (!S_ISREG(st.st_mode))
            throw InvalidInput(where + ", attribute " + a->Name(), "'" + candidate + "' is not a regular file");
          if (assets.insert(candidate).second) {
            const std::uint64_t size = static_cast<std::uint64_t>(st.st_size);
            if (out.bytes + size > limits.max_input_bytes) throw over_budget(where, size);
            out.bytes += size;
          }
          break;
        }
      }
    }
    const long most = std::min(limits.max_bodies, limits.max_mjcf_bodies);
    if (out.declared_bodies > most)
      throw limitExceeded(path, "bodies (declared in its files, before MuJoCo's compiler, whose time grows as their "
                                "square, runs)",
                          static_cast<double>(out.declared_bodies), static_cast<double>(most), "`max_bodies`");
  }
  return out;
}

}  // namespace model_import
}  // namespace lieflow

#endif
