// MuJoCo MJCF models through MuJoCo's own compiler (Debian libmujoco-dev):
// model_readers.hpp. Defaults, classes, frames, angle units, Euler sequences
// and inertias from geoms are as MuJoCo reads them, because it is MuJoCo
// that reads them; this file maps the compiled mjModel at qpos0.
#include "model/import/model_readers.hpp"

#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

#ifdef LIEFLOW_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#include <tinyxml2.h>

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <sstream>
#include <type_traits>

#include "model/import/mjcf_files.hpp"
#include "model/import/mjcf_model.hpp"
#include "model/import/model_to_scene.hpp"
#include "model/import/xml_lines.hpp"
#endif

namespace lieflow {

#ifndef LIEFLOW_HAVE_MUJOCO

bool canReadMjcf() { return false; }

namespace model_import {
ModelDescription readMjcf(const std::string&, const std::string& path, const ModelImportOptions&,
                          const ResourceLimits&) {
  throw InvalidInput(path, "reading MuJoCo MJCF needs MuJoCo's compiler, which this lieflow was built without "
                           "(apt-get install libmujoco-dev libtinyxml2-dev, then rebuild lieflow)");
}
}  // namespace model_import

#else

bool canReadMjcf() { return true; }

namespace model_import {

namespace {

/// Two hinges of one body make a universal joint when their axes are
/// orthogonal to this |cos| (through one point, or offset: universal.hpp,
/// offset_universal.hpp); three make a gimbal (gimbal.hpp) when they are
/// also through one point to kSameAnchorPoint (m).
constexpr double kOrthogonal = 1e-9;
constexpr double kSameAnchorPoint = 1e-12;


static_assert(std::is_same<mjtNum, double>::value, "lieflow reads MuJoCo built with double mjtNum");
Eigen::Vector3d vec3(const mjtNum* x) { return mjVec3(x); }
Eigen::Matrix3d mat3(const mjtNum* x) { return mjMat3(x); }

std::string nameOf(const mjModel* m, int type, int id, const char* kind) {
  const char* n = mj_id2name(m, type, id);
  if (n && *n) return n;
  return std::string(kind) + " " + std::to_string(id);
}

}  // namespace

std::string mjcfBodyName(const mjModel* m, int b) { return nameOf(m, mjOBJ_BODY, b, "body"); }

namespace {

/// A keyframe's gap in a closure that holds at qpos0 beyond this (m, rad)
/// refuses the keyframe.
constexpr double kKeyframeClosureGap = 1e-9;

std::string keyframeName(const mjModel* m, int key) {
  const char* n = mj_id2name(m, mjOBJ_KEY, key);
  return n && *n ? std::string(n) : std::to_string(key);
}

}  // namespace

void MjcfModelDeleter::operator()(mjModel_* m) const { mj_deleteModel(m); }
void MjcfDataDeleter::operator()(mjData_* d) const { mj_deleteData(d); }

namespace {

/// The guard that is active (one at a time: MuJoCo's handlers are global).
thread_local MujocoMessageGuard* g_guard = nullptr;

void keepMujocoWarning(const char* text) {
  if (g_guard) g_guard->keep(text);
}

void raiseMujocoError(const char* text) { throw MujocoError(text); }

}  // namespace

MujocoMessageGuard::MujocoMessageGuard()
    : previous_error_(mju_user_error), previous_warning_(mju_user_warning), previous_guard_(g_guard) {
  mju_user_error = &raiseMujocoError;
  mju_user_warning = &keepMujocoWarning;
  g_guard = this;
}

MujocoMessageGuard::~MujocoMessageGuard() {
  mju_user_error = previous_error_;
  mju_user_warning = previous_warning_;
  g_guard = previous_guard_;
}

void MujocoMessageGuard::keep(const char* text) {
  std::string line(text);
  while (!line.empty() && (line.back() == '\n' || line.back() == ' ')) line.pop_back();
  warnings_ += (warnings_.empty() ? "" : "; ") + line;
}

namespace {

/// Standard error (file descriptor 2) kept in a temporary file while it
/// lives, then restored; text() reads what was written.
class CapturedStderr {
 public:
  CapturedStderr() : file_(std::tmpfile()) {
    std::fflush(stderr);
    saved_ = file_ ? ::dup(2) : -1;
    if (saved_ >= 0) ::dup2(::fileno(file_), 2);
  }
  ~CapturedStderr() {
    if (saved_ >= 0) {
      std::fflush(stderr);
      ::dup2(saved_, 2);
      ::close(saved_);
    }
    if (file_) std::fclose(file_);
  }
  CapturedStderr(const CapturedStderr&) = delete;
  CapturedStderr& operator=(const CapturedStderr&) = delete;
  std::string text() const {
    if (!file_) return "";
    std::fflush(stderr);
    std::string out;
    std::rewind(file_);
    char buffer[4096];
    for (std::size_t got; (got = std::fread(buffer, 1, sizeof buffer, file_)) > 0 && out.size() < (1u << 20);)
      out.append(buffer, got);
    return out;
  }

 private:
  std::FILE* file_;
  int saved_ = -1;
};

/// MuJoCo's compiler messages as one sentence that names the line:
/// "XML Error: REASON\nElement 'joint', line 27" and "Error: REASON\nObject
/// name = NAME, id = 3, line = 15, column = -1" become "line 27, <joint>:
/// REASON" and "line 15, 'NAME': REASON"; MuJoCo's constant names (mjMINVAL)
/// are given with their values.
/// The length of the integer at text[at] (a leading '-' if `sign`), 0 if none.
std::size_t integerAt(const std::string& text, std::size_t at, bool sign) {
  std::size_t end = at;
  if (sign && end < text.size() && text[end] == '-') ++end;
  const std::size_t digits = end;
  while (end < text.size() && std::isdigit(static_cast<unsigned char>(text[end]))) ++end;
  return end > digits ? end - at : 0;
}

/// The first "Element 'NAME', line L" in `text`.
bool findElementLine(const std::string& text, std::string* name, std::string* line) {
  const std::string head = "Element '", tail = "', line ";
  for (std::size_t at = text.find(head); at != std::string::npos; at = text.find(head, at + 1)) {
    const std::size_t quote = text.find('\'', at + head.size());
    if (quote == std::string::npos) return false;
    if (text.compare(quote, tail.size(), tail) != 0) continue;
    const std::size_t n = integerAt(text, quote + tail.size(), false);
    if (n == 0) continue;
    *name = text.substr(at + head.size(), quote - at - head.size());
    *line = text.substr(quote + tail.size(), n);
    return true;
  }
  return false;
}

/// The first "Object name = NAME, id = I, line = L" in `text` (NAME without commas).
bool findObjectLine(const std::string& text, std::string* name, std::string* id, std::string* line) {
  const std::string head = "Object name = ", id_text = ", id = ", line_text = ", line = ";
  for (std::size_t at = text.find(head); at != std::string::npos; at = text.find(head, at + 1)) {
    const std::size_t comma = text.find(',', at + head.size());
    if (comma == std::string::npos) return false;
    if (text.compare(comma, id_text.size(), id_text) != 0) continue;
    const std::size_t id_at = comma + id_text.size(), n_id = integerAt(text, id_at, true);
    if (n_id == 0 || text.compare(id_at + n_id, line_text.size(), line_text) != 0) continue;
    const std::size_t line_at = id_at + n_id + line_text.size(), n_line = integerAt(text, line_at, true);
    if (n_line == 0) continue;
    *name = text.substr(at + head.size(), comma - at - head.size());
    *id = text.substr(id_at, n_id);
    *line = text.substr(line_at, n_line);
    return true;
  }
  return false;
}

std::string compilerMessage(const std::string& raw, const std::string& printed) {
  // MuJoCo's engine errors name its own resources.
  if (raw.find("Stack overflow") != std::string::npos)
    return "MuJoCo's stack overflowed while compiling: the model needs more than its <size nstack> (or "
           "memory) gives; raise it in the model, or give it fewer bodies";
  if (raw.find("Could not allocate memory") != std::string::npos || raw.find("could not create mjData") != std::string::npos)
    return "MuJoCo could not allocate the memory the model asks for (its <size>, textures, height fields or meshes)";
  // A helper's own output (qhull's) says what it could not do: its first line.
  std::string helper;
  for (std::size_t at = 0; at < printed.size() && helper.empty();) {
    const std::size_t end = std::min(printed.find('\n', at), printed.size());
    const std::string line = printed.substr(at, end - at);
    if (line.find_first_not_of(" \t") != std::string::npos) helper = line;
    at = end + 1;
  }
  const std::string also = helper.empty() ? "" : " (it printed: " + helper.substr(0, 200) + ")";
  // The reason: every line before MuJoCo's "Element ..." or "Object name ..."
  // line, joined (a reason can run over lines).
  std::string first;
  for (std::size_t at = 0; at < raw.size();) {
    const std::size_t end = std::min(raw.find('\n', at), raw.size());
    const std::string line = raw.substr(at, end - at);
    if (line.rfind("Element '", 0) == 0 || line.rfind("Object name", 0) == 0) break;
    if (!line.empty()) first += (first.empty() ? "" : " ") + line;
    at = end + 1;
  }
  for (const char* prefix : {"XML Error: ", "Error: "})
    if (first.compare(0, std::strlen(prefix), prefix) == 0) first = first.substr(std::strlen(prefix));
  for (const auto& [name, value] : {std::pair<std::string, std::string>{"mjMINVAL", "1e-15"}, {"mjMAXVAL", "1e10"}})
    if (const std::size_t at = first.find(name); at != std::string::npos)
      first.replace(at, name.size(), value + " (MuJoCo's " + name + ")");
  // MuJoCo's "Element 'NAME', line L" or "Object name = NAME, id = I, line = L",
  // read by hand (std::regex's matcher recurses once per character).
  std::string name, id, line;
  if (findElementLine(raw, &name, &line))
    return (line != "0" ? "line " + line + ", " : std::string()) + "<" + name + ">: " + first + also;
  if (findObjectLine(raw, &name, &id, &line)) {
    const std::string who = name.empty() ? "element " + id : "'" + name + "'";
    return (std::stoi(line) > 0 ? "line " + line + ", " : std::string()) + who + ": " + first + also;
  }
  std::string one_line = raw;
  for (char& c : one_line)
    if (c == '\n') c = ' ';
  while (!one_line.empty() && one_line.back() == ' ') one_line.pop_back();
  return one_line + also;
}

}  // namespace

MjcfData makeMjcfData(const mjModel_* m, const std::string& path) {
  try {
    const MujocoMessageGuard guard;
    return MjcfData(mj_makeData(m));
  } catch (const MujocoError& e) {
    throw InvalidInput(path, "MuJoCo cannot make this model's data: " + compilerMessage(e.what(), ""));
  } catch (const std::bad_alloc&) {
    throw InvalidInput(path, "MuJoCo cannot make this model's data: it asks for more memory than this machine gives");
  }
}

namespace {

/// MuJoCo's compiler on `file` (looked up in `vfs` first when given), its
/// errors as InvalidInput naming `field`.
MjcfModel compileFile(const char* file, const mjVFS* vfs, const std::string& field) {
  const std::string& path = field;
  char error[1024] = "";
  MjcfModel m;
  std::string warnings, printed;
  try {
    const MujocoMessageGuard guard;
    // Parts of the compiler print to stderr themselves (qhull, building a
    // mesh's convex hull): kept, and given with the error if it fails.
    const CapturedStderr capture;
    try {
      m.reset(mj_loadXML(file, vfs, error, sizeof(error)));
    } catch (...) {
      printed = capture.text();
      throw;
    }
    printed = capture.text();
    warnings = guard.warnings();
  } catch (const MujocoError& e) {
    throw InvalidInput(path, "MuJoCo's compiler refuses it: " + compilerMessage(e.what(), printed));
  } catch (const std::bad_alloc&) {
    throw InvalidInput(path, "MuJoCo's compiler ran out of memory: the model asks for more than this machine gives "
                             "(its <size>, textures, height fields or meshes)");
  }
  if (!m)
    throw InvalidInput(path, "MuJoCo's compiler refuses it: " + compilerMessage(*error ? error : warnings, printed));
  return m;
}

}  // namespace

MjcfModel compileMjcf(const std::string& path) { return compileFile(path.c_str(), nullptr, path); }

MjcfModel compileModelFiles(const std::vector<std::pair<std::string, std::string>>& files,
                            const std::string& field) {
  if (files.empty()) throw InvalidInput(field, "no model text to compile");
  if (files.size() > static_cast<std::size_t>(mjMAXVFS))
    throw InvalidInput(field, "MuJoCo holds at most " + std::to_string(mjMAXVFS) + " files in memory");
  // mj_loadXML reads files only: the texts are files of a virtual file system.
  // mjVFS holds 2000 file names of 1000 bytes: on the heap, not the stack.
  struct Vfs {
    mjVFS vfs;
    Vfs() { mj_defaultVFS(&vfs); }
    ~Vfs() { mj_deleteVFS(&vfs); }
  };
  const auto vfs = std::make_unique<Vfs>();
  for (const auto& [name, text] : files) {
    if (mj_makeEmptyFileVFS(&vfs->vfs, name.c_str(), static_cast<int>(text.size())) != 0)
      throw InvalidInput(field, "MuJoCo cannot hold '" + name + "' in memory");
    std::memcpy(vfs->vfs.filedata[mj_findFileVFS(&vfs->vfs, name.c_str())], text.data(), text.size());
  }
  return compileFile(files[0].first.c_str(), &vfs->vfs, field);
}

MjcfModel compileModelText(const std::string& name, const std::string& text, const std::string& field) {
  return compileModelFiles({{name, text}}, field);
}

int keyframeIndex(const mjModel* m, const std::string& path, const std::string& wanted) {
  if (wanted.empty()) return -1;
  const int by_name = mj_name2id(m, mjOBJ_KEY, wanted.c_str());
  if (by_name >= 0) return by_name;
  if (wanted.find_first_not_of("0123456789") == std::string::npos && wanted.size() < 9) {
    const int index = std::stoi(wanted);
    if (index < m->nkey) return index;
  }
  std::string have;
  for (int k = 0; k < m->nkey; ++k) have += (have.empty() ? "" : ", ") + keyframeName(m, k);
  throw InvalidInput(path + ": `keyframe`", "the model has no keyframe '" + wanted + "' (" +
                                                (m->nkey == 0 ? std::string("it has no <key>") : "it has " + have) + ")");
}

bool representedEquality(const mjModel* m, int e) {
  const int type = m->eq_type[e];
  const mjtNum* c = m->eq_data + e * mjNEQDATA;
  const bool linear_coupling = type == mjEQ_JOINT && m->eq_obj2id[e] >= 0 && c[2] == 0 && c[3] == 0 && c[4] == 0;
  return type == mjEQ_CONNECT || type == mjEQ_WELD || linear_coupling;
}

namespace {

/// How far a closure that holds at qpos0 (d0) is from holding in d: the
/// distance between the two bodies' copies of the connect point (`point`,
/// body 1's frame), or for a weld the change of body 2's pose in body 1's
/// frame (position and angle).
double closureGap(const mjData* d0, const mjData* d, int b1, int b2, const Eigen::Vector3d& point, bool weld) {
  const auto pose = [](const mjData* x, int b) {
    return std::make_pair(b == 0 ? Eigen::Matrix3d::Identity().eval() : mat3(x->xmat + 9 * b),
                          b == 0 ? Eigen::Vector3d::Zero().eval() : vec3(x->xpos + 3 * b));
  };
  const auto [R1a, x1a] = pose(d0, b1);
  const auto [R2a, x2a] = pose(d0, b2);
  const auto [R1b, x1b] = pose(d, b1);
  const auto [R2b, x2b] = pose(d, b2);
  if (!weld) {
    const Eigen::Vector3d on2 = R2a.transpose() * (x1a + R1a * point - x2a);  // body 2's copy, its frame
    return ((x1b + R1b * point) - (x2b + R2b * on2)).norm();
  }
  const Eigen::Matrix3d rel_a = R1a.transpose() * R2a, rel_b = R1b.transpose() * R2b;
  const double angle = Eigen::AngleAxisd(rel_a.transpose() * rel_b).angle();
  return std::max(angle, (R1a.transpose() * (x2a - x1a) - R1b.transpose() * (x2b - x1b)).norm());
}

}  // namespace

namespace {

/// Lines of the model file's bodies, joints, geoms and equalities in
/// document order, which is MuJoCo's numbering of them: the line of an
/// unnamed element by its id, when the file holds as many as the model
/// (an <include> or a <composite> adds elements the main file does not show).
class ElementLines {
 public:
  explicit ElementLines(const XmlLines& xml) {
    for (const tinyxml2::XMLElement* e : xml.elements()) {
      const std::string tag = e->Name();
      const tinyxml2::XMLElement* up = e->Parent() ? e->Parent()->ToElement() : nullptr;
      if (tag == "body") bodies_.push_back(e->GetLineNum());
      if (tag == "joint" || tag == "freejoint") joints_.push_back(e->GetLineNum());
      if (tag == "geom") geoms_.push_back(e->GetLineNum());
      if (up && std::string(up->Name()) == "equality") equalities_.push_back(e->GetLineNum());
    }
  }
  int line(const mjModel* m, int type, int id) const {
    const auto at = [](const std::vector<int>& lines, int count, int k) {
      return static_cast<int>(lines.size()) == count && k >= 0 && k < count ? lines[static_cast<std::size_t>(k)] : 0;
    };
    switch (type) {
      case mjOBJ_BODY: return at(bodies_, m->nbody - 1, id - 1);  // body 0 is the world
      case mjOBJ_JOINT: return at(joints_, m->njnt, id);
      case mjOBJ_GEOM: return at(geoms_, m->ngeom, id);
      case mjOBJ_EQUALITY: return at(equalities_, m->neq, id);
      default: return 0;
    }
  }

 private:
  std::vector<int> bodies_, joints_, geoms_, equalities_;
};

/// Below this norm a quaternion in a keyframe's qpos is refused: MuJoCo
/// would turn it silently into the identity.
constexpr double kMinKeyframeQuaternionNorm = 1e-6;

/// The qpos of keyframe `key` as the file writes it: MuJoCo's compiler
/// normalizes the keyframes' quaternions (one of norm 0 becomes the
/// identity), so they are read from the <key> element itself; the compiled
/// values when the element is not in the model's own file.
std::vector<double> writtenKeyQpos(const mjModel* m, int key, const XmlLines& xml) {
  int index = 0;
  for (const tinyxml2::XMLElement* e : xml.elements()) {
    if (std::string(e->Name()) != "key") continue;
    if (index++ != key) continue;
    std::vector<double> q;
    if (const char* text = e->Attribute("qpos")) {
      std::istringstream values(text);
      for (double x = 0.0; values >> x;) q.push_back(x);
    }
    if (static_cast<int>(q.size()) == m->nq) return q;
  }
  return std::vector<double>(m->key_qpos + key * m->nq, m->key_qpos + (key + 1) * m->nq);
}

/// The keyframe's quaternions (free and ball joints), as written, have a
/// norm MuJoCo can normalize; else InvalidInput naming the key, the joint and
/// the entries.
void requireUnitQuaternions(const mjModel* m, const std::string& path, int key, const XmlLines& xml) {
  const std::vector<double> qpos = writtenKeyQpos(m, key, xml);
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_FREE && m->jnt_type[j] != mjJNT_BALL) continue;
    const int at = m->jnt_qposadr[j] + (m->jnt_type[j] == mjJNT_FREE ? 3 : 0);
    const double* q = qpos.data() + at;
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(norm >= kMinKeyframeQuaternionNorm)) {
      const std::string name = keyframeName(m, key);
      throw InvalidInput(path + ": " + elementLabel("key", name, xml.line("key", name)) + ", attribute qpos",
                         "the quaternion of joint '" + nameOf(m, mjOBJ_JOINT, j, "joint") + "' (qpos[" +
                             std::to_string(at) + ".." + std::to_string(at + 3) + "]) has norm " +
                             formatNumber(norm) + ": it gives no orientation");
    }
  }
}

}  // namespace

ModelDescription readMjcf(const std::string& text, const std::string& path, const ModelImportOptions& options,
                          const ResourceLimits& limits) {
  const XmlLines xml(text, path);
  if (xml.rootTag() != "mujoco")
    throw InvalidInput(path, "an MJCF file's root element is <mujoco>, not <" + xml.rootTag() + ">");
  checkMjcfFiles(path, text, limits);
  const MjcfModel m = compileMjcf(path);
  // Poses and the bodies' velocities (mj_comVel) at qpos0 and at rest, or
  // at the keyframe if one is asked for (d); then also at qpos0 (d0), where
  // the model's closures hold.
  const MjcfData d = makeMjcfData(m.get(), path);
  const int key = keyframeIndex(m.get(), path, options.keyframe);
  if (!(m->opt.timestep > 0.0))
    throw InvalidInput(path + ": option, attribute timestep", "must be positive, got " + formatNumber(m->opt.timestep));
  if (key >= 0) requireUnitQuaternions(m.get(), path, key, xml);
  MjcfData d0;
  if (key >= 0) {
    mju_copy(d->qpos, m->key_qpos + key * m->nq, m->nq);
    mju_copy(d->qvel, m->key_qvel + key * m->nv, m->nv);
    d0 = makeMjcfData(m.get(), path);
    mj_kinematics(m.get(), d0.get());
  }
  mj_kinematics(m.get(), d.get());
  mj_comPos(m.get(), d.get());
  mj_comVel(m.get(), d.get());

  ModelDescription model;
  model.source = path;
  model.name = nameOf(m.get(), mjOBJ_BODY, 0, "model");
  if (const char* n = mj_id2name(m.get(), mjOBJ_BODY, 0); !n || std::string(n) == "world") {
    const std::string file = path.substr(path.find_last_of('/') + 1);
    model.name = file.substr(0, file.find_last_of('.'));
  }
  // MuJoCo's own switches, taken as MuJoCo takes them: gravity and the
  // joints' springs and dashpots (passive forces) can be off, and so can the
  // equality constraints (alone, or with every constraint).
  const int off = m->opt.disableflags;
  const bool passive = !(off & mjDSBL_PASSIVE);
  const bool equalities = !(off & mjDSBL_EQUALITY) && !(off & mjDSBL_CONSTRAINT);
  model.gravity = off & mjDSBL_GRAVITY ? Eigen::Vector3d::Zero() : vec3(m->opt.gravity);
  model.timestep = m->opt.timestep;
  // An element's line: by its name, or for an unnamed one by its place
  // among the file's elements of its kind (MuJoCo numbers bodies, joints,
  // geoms and equalities in document order), when the file holds them all.
  const ElementLines unnamed(xml);
  auto line = [&](const char* tag, int type, int id) {
    const char* n = mj_id2name(m.get(), type, id);
    // (Equalities are <connect>, <weld>, <joint> ... elements: by place.)
    if (n && *n && type != mjOBJ_EQUALITY) return xml.line(tag, n);
    return unnamed.line(m.get(), type, id);
  };
  auto label = [&](const char* tag, int type, int id) {
    return elementLabel(tag, nameOf(m.get(), type, id, tag), line(tag, type, id));
  };

  // What lieflow does not represent.
  UnsupportedFeatures unsupported;
  if (!(m->opt.disableflags & mjDSBL_CONTACT))
    for (int g = 0; g < m->ngeom; ++g)
      if (m->geom_contype[g] || m->geom_conaffinity[g]) unsupported.add("contacts", label("geom", mjOBJ_GEOM, g));
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_limited[j]) unsupported.add("limits", label("joint", mjOBJ_JOINT, j));
    const int dof = m->jnt_dofadr[j];
    const int ndof = m->jnt_type[j] == mjJNT_FREE ? 6 : m->jnt_type[j] == mjJNT_BALL ? 3 : 1;
    bool armature = false, friction = false;
    for (int k = dof; k < dof + ndof; ++k) {
      armature = armature || m->dof_armature[k] != 0.0;
      friction = friction || m->dof_frictionloss[k] != 0.0;
    }
    if (armature) unsupported.add("armature", label("joint", mjOBJ_JOINT, j));
    if (friction) unsupported.add("friction", label("joint", mjOBJ_JOINT, j));
  }
  for (int u = 0; u < m->nu; ++u) unsupported.add("actuators", label("actuator", mjOBJ_ACTUATOR, u));
  for (int t = 0; t < m->ntendon; ++t) unsupported.add("tendons", label("tendon", mjOBJ_TENDON, t));
  for (int e = 0; e < m->neq; ++e)
    if (!representedEquality(m.get(), e)) unsupported.add("equalities", label("equality", mjOBJ_EQUALITY, e));
  // The medium's forces (lift, drag and buoyancy from density, viscosity and
  // wind), which lieflow has no model of.
  if (m->opt.density != 0.0 || m->opt.viscosity != 0.0 || vec3(m->opt.wind).squaredNorm() != 0.0)
    unsupported.add("fluid", "option (line " + std::to_string(xml.firstLine("option")) + "): density " +
                                 formatNumber(m->opt.density) + ", viscosity " + formatNumber(m->opt.viscosity) +
                                 ", wind " + formatNumbers(vec3(m->opt.wind)));
  unsupported.resolve(options, &model);

  model.ground_visuals = mjcfBodyShapes(m.get(), d.get(), 0);
  // Links: every body but the world (body 0), at qpos0.
  for (int b = 1; b < m->nbody; ++b) {
    ModelLink l;
    l.name = mjcfBodyName(m.get(), b);
    l.line = line("body", mjOBJ_BODY, b);
    if (l.name == "ground")
      throw InvalidInput(path + ": " + elementLabel("body", l.name, l.line),
                         "'ground' is lieflow's name for the world: rename the body");
    if (m->body_mocapid[b] >= 0)
      throw InvalidInput(path + ": " + elementLabel("body", l.name, l.line),
                         "is a mocap body (moved by the user, not by dynamics): lieflow cannot simulate it");
    l.mass = m->body_mass[b];
    l.com_world = vec3(d->xipos + 3 * b);
    const Eigen::Matrix3d Ri = mat3(d->ximat + 9 * b);
    l.inertia_world = Ri * vec3(m->body_inertia + 3 * b).asDiagonal() * Ri.transpose();
    l.orientation = Eigen::Quaterniond(d->xquat[4 * b], d->xquat[4 * b + 1], d->xquat[4 * b + 2], d->xquat[4 * b + 3]);
    mjtNum velocity[6];  // (ω, v of the centre of mass), world
    mj_objectVelocity(m.get(), d.get(), mjOBJ_BODY, b, velocity, 0);
    l.angular_velocity_world = vec3(velocity);
    l.velocity_world = vec3(velocity + 3);
    l.visuals = mjcfBodyShapes(m.get(), d.get(), b);
    model.links.push_back(l);
  }
  auto link = [](int body) { return body - 1; };  // the world is −1

  // Joints: a body's joints to its parent (none: welded).
  std::map<int, int> scene_joint_of_mj;  // MuJoCo joint → model joint (hinges, slides)
  for (int b = 1; b < m->nbody; ++b) {
    const int first = m->body_jntadr[b], count = m->body_jntnum[b];
    ModelJoint mj;
    mj.parent = link(m->body_parentid[b]);
    mj.child = link(b);
    const std::string body_label = elementLabel("body", model.links[link(b)].name, model.links[link(b)].line);
    if (count == 0) {
      mj.type = ModelJointType::kFixed;
      mj.name = model.links[link(b)].name + "-weld";
      mj.line = model.links[link(b)].line;
      model.joints.push_back(mj);
      continue;
    }
    const int j0 = first;
    mj.name = nameOf(m.get(), mjOBJ_JOINT, j0, "joint");
    mj.line = line("joint", mjOBJ_JOINT, j0);
    mj.anchor_world = vec3(d->xanchor + 3 * j0);
    mj.axis_world = vec3(d->xaxis + 3 * j0);
    auto coordinate = [&](int j, int i) {
      const int q = m->jnt_qposadr[j];
      mj.initial[i] = d->qpos[q];
      mj.stiffness[i] = passive ? m->jnt_stiffness[j] : 0.0;
      mj.rest[i] = m->qpos_spring[q];
      mj.damping[i] = passive ? m->dof_damping[m->jnt_dofadr[j]] : 0.0;
    };
    const int type = m->jnt_type[j0];
    if (count == 1) {
      if (type == mjJNT_FREE) {
        if (mj.parent != -1)
          throw InvalidInput(path + ": " + elementLabel("joint", mj.name, mj.line), "a free joint must be on a top-level body");
        mj.type = ModelJointType::kFree;
      } else if (type == mjJNT_BALL) {
        mj.type = ModelJointType::kSpherical;
        if (m->jnt_stiffness[j0] != 0.0 || m->dof_damping[m->jnt_dofadr[j0]] != 0.0)
          throw InvalidInput(path + ": " + elementLabel("joint", mj.name, mj.line),
                             "a ball joint with stiffness or damping: lieflow's spherical joint has no coordinate "
                             "to carry them");
      } else {
        mj.type = type == mjJNT_SLIDE ? ModelJointType::kPrismatic : ModelJointType::kRevolute;
        coordinate(j0, 0);
        scene_joint_of_mj[j0] = static_cast<int>(model.joints.size());
      }
      model.joints.push_back(mj);
      continue;
    }
    // Two hinges with orthogonal axes: a universal joint (offset when the
    // second passes through another point); three through one point with
    // orthogonal axes: a gimbal.
    const int j1 = first + 1, j2 = first + 2;
    bool hinges = true;
    for (int j = first; j < first + count; ++j) hinges = hinges && m->jnt_type[j] == mjJNT_HINGE;
    auto orthogonal = [&](int p, int q) {
      return std::abs(vec3(d->xaxis + 3 * p).dot(vec3(d->xaxis + 3 * q))) <= kOrthogonal;
    };
    const bool universal = count == 2 && hinges && orthogonal(j0, j1);
    const bool gimbal = count == 3 && hinges && orthogonal(j0, j1) && orthogonal(j0, j2) && orthogonal(j1, j2) &&
                        (vec3(d->xanchor + 3 * j1) - mj.anchor_world).norm() <= kSameAnchorPoint &&
                        (vec3(d->xanchor + 3 * j2) - mj.anchor_world).norm() <= kSameAnchorPoint;
    if (gimbal) {
      mj.type = ModelJointType::kGimbal;
      mj.name = mj.name + "+" + nameOf(m.get(), mjOBJ_JOINT, j1, "joint") + "+" + nameOf(m.get(), mjOBJ_JOINT, j2, "joint");
      mj.axis2_world = vec3(d->xaxis + 3 * j1);
      mj.axis3_world = vec3(d->xaxis + 3 * j2);
      for (int i = 0; i < 3; ++i) coordinate(first + i, i);
      model.joints.push_back(mj);
      continue;
    }
    if (!universal) {
      std::string names;
      for (int j = first; j < first + count; ++j) names += (names.empty() ? "" : ", ") + nameOf(m.get(), mjOBJ_JOINT, j, "joint");
      throw InvalidInput(path + ": " + body_label,
                         "has " + std::to_string(count) + " joints (" + names +
                             "): lieflow joins two bodies by one joint; two hinges with orthogonal axes make "
                             "a universal joint, three through one point with orthogonal axes a gimbal, other "
                             "combinations are not represented");
    }
    mj.type = ModelJointType::kUniversal;
    mj.name = mj.name + "+" + nameOf(m.get(), mjOBJ_JOINT, j1, "joint");
    mj.axis2_world = vec3(d->xaxis + 3 * j1);
    mj.anchor2_world = vec3(d->xanchor + 3 * j1);
    coordinate(j0, 0);
    coordinate(j1, 1);
    model.joints.push_back(mj);
  }

  // Equality constraints: connect → spherical, weld → fixed, joint → coupling.
  for (int e = 0; e < m->neq && equalities; ++e) {
    if (!m->eq_active[e]) continue;
    const int type = m->eq_type[e];
    const mjtNum* c = m->eq_data + e * mjNEQDATA;
    const std::string name = nameOf(m.get(), mjOBJ_EQUALITY, e, "equality");
    const int eline = line("equality", mjOBJ_EQUALITY, e);
    if (type == mjEQ_CONNECT || type == mjEQ_WELD) {
      ModelClosure cl;
      cl.name = name;
      cl.line = eline;
      cl.type = type == mjEQ_CONNECT ? ModelJointType::kSpherical : ModelJointType::kFixed;
      const int b1 = m->eq_obj1id[e], b2 = m->eq_obj2id[e];
      cl.link1 = link(b1);
      cl.link2 = link(b2);
      // connect: the anchor in body 1's frame; weld: body 2's origin.
      cl.anchor_world = type == mjEQ_CONNECT ? Eigen::Vector3d(vec3(d->xpos + 3 * b1) + mat3(d->xmat + 9 * b1) * vec3(c))
                                             : vec3(d->xpos + 3 * b2);
      // MuJoCo takes the constraint as satisfied at qpos0: a keyframe must
      // keep it (else the scene would close the loop somewhere else).
      if (key >= 0) {
        const double gap = closureGap(d0.get(), d.get(), b1, b2, type == mjEQ_CONNECT ? vec3(c) : Eigen::Vector3d::Zero(),
                                      type == mjEQ_WELD);
        if (gap > kKeyframeClosureGap)
          throw InvalidInput(path + ": `keyframe`", "keyframe '" + keyframeName(m.get(), key) + "' breaks " +
                                                        elementLabel("equality", name, eline) + " (by " +
                                                        formatNumber(gap) + " m or rad), which holds at qpos0");
      }
      model.closures.push_back(cl);
    } else if (type == mjEQ_JOINT && m->eq_obj2id[e] >= 0) {
      const int follower = m->eq_obj1id[e], leader = m->eq_obj2id[e];
      if (!scene_joint_of_mj.count(follower) || !scene_joint_of_mj.count(leader))
        throw InvalidInput(path + ": " + elementLabel("equality", name, eline),
                           "couples joints lieflow cannot couple (a gear row joins two single hinges of one parent)");
      ModelCoupling g;
      g.name = name;
      g.line = eline;
      g.leader = model.joints[scene_joint_of_mj[leader]].name;
      g.follower = model.joints[scene_joint_of_mj[follower]].name;
      g.multiplier = c[1];
      // MuJoCo: q₁ − q₁⁰ = a₀ + a₁ (q₂ − q₂⁰); here q_f = a₁ q_l + offset.
      g.offset = c[0] + m->qpos0[m->jnt_qposadr[follower]] - c[1] * m->qpos0[m->jnt_qposadr[leader]];
      model.couplings.push_back(g);
    }
  }
  return model;
}

}  // namespace model_import

#endif

}  // namespace lieflow
