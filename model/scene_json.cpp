/// \file
/// Strict reading of scene files: every field is checked for presence, type,
/// finiteness and physical sense, unknown fields are errors, and every error
/// names the file, the field and the reason.
#include <cmath>
#include <functional>
#include <set>
#include <sstream>
#include <unordered_map>
#include <vector>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "model/import/model_import.hpp"
#include "model/input_file.hpp"
#include "liegroup/input_number.hpp"
#include "model/scene.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace {

using json = nlohmann::json;

/// Relative tolerance of the inertia checks (symmetry, triangle inequality).
constexpr double kInertiaTolerance = 1e-9;

std::string typeName(const json& v) {
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_boolean()) return "a boolean";
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return "null";
}

/// A JSON object whose fields are read one by one; `finish()` rejects the
/// fields nobody asked for.
class ObjectReader {
 public:
  ObjectReader(const json& object, std::string path, std::string source)
      : object_(object), path_(std::move(path)), source_(std::move(source)) {
    if (!object_.is_object()) fail("", "expected an object, got " + typeName(object_));
  }

  [[noreturn]] void fail(const std::string& key, const std::string& reason) const {
    std::string field = path_;
    if (!key.empty()) field += (field.empty() ? "" : ".") + key;
    throw InvalidInput(source_ + ": " + (field.empty() ? "(top level)" : field), reason);
  }

  std::string fieldPath(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }

  bool has(const std::string& key) const { return object_.contains(key); }

  const json& get(const std::string& key) {
    if (!object_.contains(key)) fail(key, "missing (required)");
    known_.insert(key);
    return object_.at(key);
  }

  double number(const std::string& key) {
    const json& v = get(key);
    return checkedNumber(v, key);
  }

  double positiveNumber(const std::string& key) {
    const double v = number(key);
    if (const std::string problem = positiveInputProblem(v); !problem.empty()) fail(key, problem);
    return v;
  }

  std::string string(const std::string& key) {
    const json& v = get(key);
    if (!v.is_string()) fail(key, "expected a string, got " + typeName(v));
    const std::string s = v.get<std::string>();
    if (s.empty()) fail(key, "must not be empty");
    return s;
  }

  bool boolean(const std::string& key) {
    const json& v = get(key);
    if (!v.is_boolean()) fail(key, "expected true or false, got " + typeName(v));
    return v.get<bool>();
  }

  Eigen::VectorXd numbers(const std::string& key, int expected_size) {
    const json& v = get(key);
    if (!v.is_array()) fail(key, "expected an array of " + std::to_string(expected_size) + " numbers, got " + typeName(v));
    if (static_cast<int>(v.size()) != expected_size)
      fail(key, "expected " + std::to_string(expected_size) + " numbers, got " + std::to_string(v.size()));
    Eigen::VectorXd out(expected_size);
    for (int i = 0; i < expected_size; ++i) out[i] = checkedNumber(v[i], key + "[" + std::to_string(i) + "]");
    return out;
  }

  Eigen::Vector3d vector3(const std::string& key) { return numbers(key, 3); }

  const json& array(const std::string& key) {
    const json& v = get(key);
    if (!v.is_array()) fail(key, "expected an array, got " + typeName(v));
    return v;
  }

  /// Rejects fields that were not read.
  void finish() const {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      if (known_.count(it.key())) continue;
      fail(it.key(), "unknown field");
    }
  }

  void accept(const std::string& key) { known_.insert(key); }

  const std::string& source() const { return source_; }

 private:
  double checkedNumber(const json& v, const std::string& key) const {
    if (!v.is_number()) fail(key, "expected a number, got " + typeName(v));
    const double x = v.get<double>();
    if (const std::string problem = inputNumberProblem(x); !problem.empty()) fail(key, problem);
    return x;
  }


  const json& object_;
  std::string path_;
  std::string source_;
  std::set<std::string> known_;
};

/// Inertia: 3 principal moments, or a 3×3 symmetric matrix (array of 3 rows
/// or 9 numbers). Must be symmetric positive definite and satisfy the
/// triangle inequality of principal moments (a physical mass distribution).
Eigen::Matrix3d readInertia(ObjectReader& body) {
  const json& v = body.get("inertia");
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
  auto element = [&](const json& x, const std::string& where) {
    if (!x.is_number()) body.fail("inertia", where + " expected a number, got " + typeName(x));
    const double d = x.get<double>();
    if (const std::string problem = inputNumberProblem(d); !problem.empty()) body.fail("inertia", where + " " + problem);
    return d;
  };
  if (v.is_array() && v.size() == 3 && v[0].is_number()) {
    for (int i = 0; i < 3; ++i) J(i, i) = element(v[i], "entry " + std::to_string(i));
  } else if (v.is_array() && v.size() == 3 && v[0].is_array()) {
    for (int i = 0; i < 3; ++i) {
      if (!v[i].is_array() || v[i].size() != 3) body.fail("inertia", "a 3×3 matrix needs 3 rows of 3 numbers");
      for (int j = 0; j < 3; ++j)
        J(i, j) = element(v[i][j], "entry (" + std::to_string(i) + "," + std::to_string(j) + ")");
    }
  } else if (v.is_array() && v.size() == 9) {
    for (int k = 0; k < 9; ++k) J(k / 3, k % 3) = element(v[k], "entry " + std::to_string(k));
  } else {
    body.fail("inertia", "expected 3 principal moments or a 3×3 symmetric matrix");
  }
  const double scale = J.cwiseAbs().maxCoeff();
  if (!(scale > 0.0)) body.fail("inertia", "is zero (a body needs rotary inertia)");
  if ((J - J.transpose()).cwiseAbs().maxCoeff() > kInertiaTolerance * scale)
    body.fail("inertia", "matrix is not symmetric");
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(J).eigenvalues();
  if (!(moments.minCoeff() > 0.0))
    body.fail("inertia", "is not positive definite (principal moments " + formatNumbers(moments) + ")");
  if (moments.minCoeff() < kMinPositiveInput)
    body.fail("inertia", "principal moment " + formatNumber(moments.minCoeff()) + " is below " +
                             formatNumber(kMinPositiveInput) + ", the smallest positive value lieflow reads");
  // Principal moments of a real body: I_a + I_b ≥ I_c for every permutation.
  if (moments[0] + moments[1] < moments[2] * (1.0 - kInertiaTolerance))
    body.fail("inertia", "principal moments " + formatNumbers(moments) +
                             " violate the triangle inequality I1 + I2 >= I3 (no mass distribution has them)");
  return J;
}

BodyDescription readBody(const json& v, int index, const std::string& source) {
  ObjectReader r(v, "bodies[" + std::to_string(index) + "]", source);
  BodyDescription b;
  b.name = r.string("name");
  if (const std::string problem = columnNameProblem(b.name); !problem.empty()) r.fail("name", problem);
  if (b.name == "ground") r.fail("name", "'ground' is the fixed world frame, not a body name");
  b.mass = r.positiveNumber("mass");
  b.inertia = readInertia(r);
  if (r.has("rotation_only")) b.rotation_only = r.boolean("rotation_only");
  if (r.has("orientation")) {
    const Eigen::VectorXd q = r.numbers("orientation", 4);
    b.orientation = SO3d::fromQuaternionChecked(Eigen::Quaterniond(q[0], q[1], q[2], q[3]),
                                                source + ": " + r.fieldPath("orientation"))
                        .quaternion();
  }
  if (r.has("position")) {
    b.position = r.vector3("position");
    b.has_position = true;
  }
  if (r.has("angular_velocity")) b.angular_velocity = r.vector3("angular_velocity");
  if (r.has("velocity")) {
    b.velocity = r.vector3("velocity");
    b.has_velocity = true;
  }
  if (r.has("sensor")) b.sensor = r.vector3("sensor");
  if (r.has("torsional_spring")) {
    ObjectReader spring(r.get("torsional_spring"), r.fieldPath("torsional_spring"), source);
    b.spring_stiffness = spring.positiveNumber("stiffness");
    if (spring.has("rest_orientation")) {
      const Eigen::VectorXd q = spring.numbers("rest_orientation", 4);
      b.spring_rest = SO3d::fromQuaternionChecked(Eigen::Quaterniond(q[0], q[1], q[2], q[3]),
                                                  source + ": " + spring.fieldPath("rest_orientation"))
                          .quaternion();
    }
    spring.finish();
  }
  r.finish();
  return b;
}

/// A time function: a number (constant) or {"type": "constant" | "ramp" |
/// "sine" | "table", ...} (model/time_function.hpp).
TimeFunction readTimeFunction(ObjectReader& parent, const std::string& key) {
  const json& v = parent.get(key);
  if (v.is_number()) {
    const double x = v.get<double>();
    if (const std::string problem = inputNumberProblem(x); !problem.empty()) parent.fail(key, problem);
    return TimeFunction::constant(x);
  }
  ObjectReader r(v, parent.fieldPath(key), parent.source());
  const std::string type = r.string("type");
  TimeFunction f;
  if (type == "constant") {
    f = TimeFunction::constant(r.number("value"));
  } else if (type == "ramp") {
    f = TimeFunction::ramp(r.has("initial") ? r.number("initial") : 0.0, r.number("rate"));
  } else if (type == "sine") {
    const double amplitude = r.number("amplitude");
    const double frequency = r.number("frequency");
    if (frequency < 0.0) r.fail("frequency", "must be >= 0 (Hz)");
    f = TimeFunction::sine(amplitude, frequency, r.has("phase") ? r.number("phase") : 0.0,
                                      r.has("offset") ? r.number("offset") : 0.0);
  } else if (type == "table") {
    f.kind = TimeFunction::Kind::kTable;
    const json& pts = r.array("points");
    if (pts.size() < 2) r.fail("points", "a table needs at least 2 points [t, value]");
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const std::string where = "points[" + std::to_string(i) + "]";
      if (!pts[i].is_array() || pts[i].size() != 2 || !pts[i][0].is_number() || !pts[i][1].is_number())
        r.fail(where, "expected [t, value]");
      const double t = pts[i][0].get<double>(), x = pts[i][1].get<double>();
      for (const double value : {t, x})
        if (const std::string problem = inputNumberProblem(value); !problem.empty()) r.fail(where, problem);
      if (i > 0 && !(t > f.points.back().first)) r.fail(where, "times must increase strictly");
      f.points.emplace_back(t, x);
    }
  } else {
    r.fail("type", "unknown time function '" + type + "' (known: constant, ramp, sine, table)");
  }
  r.finish();
  return f;
}

/// The coordinate fields of a revolute (suffix "") or universal ("1", "2")
/// joint, or of a prismatic joint (`sliding`: the spring's `rest_position`
/// and an applied `force` instead of `rest_angle` and `moment`).
void readCoordinate(ObjectReader& r, const std::string& suffix, CoordinateDescription* c, bool sliding = false) {
  if (r.has("spring" + suffix)) {
    ObjectReader s(r.get("spring" + suffix), r.fieldPath("spring" + suffix), r.source());
    c->stiffness = s.number("stiffness");
    if (c->stiffness < 0.0) s.fail("stiffness", "must be >= 0");
    const char* rest = sliding ? "rest_position" : "rest_angle";
    if (s.has(rest)) c->rest_angle = s.number(rest);
    s.finish();
  }
  if (r.has("damper" + suffix)) {
    ObjectReader d(r.get("damper" + suffix), r.fieldPath("damper" + suffix), r.source());
    c->damping = d.number("damping");
    if (c->damping < 0.0) d.fail("damping", "must be >= 0");
    d.finish();
  }
  const std::string load = (sliding ? "force" : "moment") + suffix;
  if (r.has(load)) c->moment = readTimeFunction(r, load);
  if (r.has("prescribed" + suffix)) c->prescribed = readTimeFunction(r, "prescribed" + suffix);
}

NodeAxesDescription readNodeAxes(ObjectReader& r, const std::string& key) {
  ObjectReader a(r.get(key), r.fieldPath(key), r.source());
  NodeAxesDescription n;
  n.r = a.vector3("r");
  n.s = a.vector3("s");
  if (a.has("t")) {
    n.t = a.vector3("t");
    n.has_t = true;
  }
  a.finish();
  return n;
}

JointDescription readJoint(const json& v, int index, const std::string& source) {
  ObjectReader r(v, "joints[" + std::to_string(index) + "]", source);
  JointDescription j;
  j.name = r.string("name");
  if (const std::string problem = columnNameProblem(j.name); !problem.empty()) r.fail("name", problem);
  j.type = r.string("type");
  static const std::set<std::string> kTypes = {"spherical", "revolute",    "universal",    "gimbal",  "prismatic",
                                               "fixed",     "gear",        "rack_pinion",  "differential", "coupling"};
  if (!kTypes.count(j.type))
    r.fail("type", "unknown joint type '" + j.type +
                       "' (known: spherical, revolute, universal, gimbal, prismatic, fixed, gear, rack_pinion, "
                       "differential, coupling)");
  j.main = r.string("main");
  j.secondary = r.string("secondary");
  if (j.type == "spherical" || j.type == "fixed")
    for (const char* key : {"spring", "damper", "moment", "force", "prescribed"})
      if (r.has(key))
        r.fail(key, "a " + j.type +
                        " joint has no joint coordinate to carry a spring, damper, moment, force or prescribed "
                        "motion (use a revolute, universal or prismatic joint)");
  if (!j.isGear()) {
    j.anchor_main = r.vector3("anchor_main");
    j.anchor_secondary = r.vector3("anchor_secondary");
  }
  if (j.type == "revolute") {
    j.axis_main = r.vector3("axis_main");
    if (r.has("axis_secondary")) {
      j.axis_secondary = r.vector3("axis_secondary");
      j.has_axis_secondary = true;
    }
    if (r.has("initial_angle")) j.initial_angles[0] = r.number("initial_angle");
    readCoordinate(r, "", &j.coordinates[0]);
  } else if (j.type == "gimbal") {
    j.axis_main = r.vector3("axis1_main");
    j.axis2_main = r.vector3("axis2_main");
    j.axis3_main = r.vector3("axis3_main");
    if (r.has("initial_angles")) {
      const Eigen::VectorXd a = r.numbers("initial_angles", 3);
      j.initial_angles = {{a[0], a[1], a[2]}};
    }
    for (int i = 0; i < 3; ++i) {
      const std::string suffix = std::to_string(i + 1);
      if (r.has("prescribed" + suffix))
        r.fail("prescribed" + suffix, "a gimbal's angles carry springs, dampers and moments but are not prescribed");
      readCoordinate(r, suffix, &j.coordinates[i]);
    }
  } else if (j.type == "prismatic") {
    j.axis_main = r.vector3("axis_main");
    readCoordinate(r, "", &j.coordinates[0], true);
  } else if (j.type == "universal") {
    j.axis_main = r.vector3("axis1_main");
    j.axis_secondary = r.vector3("axis2_secondary");
    j.has_axis_secondary = true;
    if (r.has("offset")) j.offset = r.boolean("offset");
    if (r.has("initial_angles")) {
      const Eigen::VectorXd a = r.numbers("initial_angles", 2);
      j.initial_angles = {{a[0], a[1], 0.0}};
    }
    readCoordinate(r, "1", &j.coordinates[0]);
    readCoordinate(r, "2", &j.coordinates[1]);
  } else if (j.isGear()) {
    j.ratio = r.number("ratio");
    if (j.ratio == 0.0) r.fail("ratio", "gear ratio is 0 (a non-zero ratio is required)");
    if (r.has("carrier")) j.carrier = r.string("carrier");
    if (j.type == "coupling") {
      // One row α q̇_main + q̇_secondary = 0 between two joints' rates: each
      // node's axis and whether it turns or slides.
      j.axes_main.r = r.vector3("axis_main");
      j.axes_secondary.r = r.vector3("axis_secondary");
      const auto motion = [&](const char* key) {
        const std::string m = r.string(key);
        if (m != "turn" && m != "slide") r.fail(key, "expected \"turn\" or \"slide\", got '" + m + "'");
        return m == "slide";
      };
      j.slide_main = motion("motion_main");
      j.slide_secondary = motion("motion_secondary");
      j.carrier_secondary = r.has("carrier_secondary") ? r.string("carrier_secondary") : j.carrier;
    } else {
      j.axes_main = readNodeAxes(r, "axes_main");
      j.axes_secondary = readNodeAxes(r, "axes_secondary");
    }
    if (j.type == "differential") {
      j.tertiary = r.string("tertiary");
      j.axes_tertiary = readNodeAxes(r, "axes_tertiary");
    }
    for (const char* key : {"main", "secondary", "tertiary"}) {
      const std::string& node = std::string(key) == "main" ? j.main
                                : std::string(key) == "secondary" ? j.secondary : j.tertiary;
      if (node == "ground")
        r.fail(key, "a gear node must be a body with rotary inertia; 'ground' has none");
    }
  }
  r.finish();
  return j;
}

}  // namespace

int SceneDescription::bodyIndex(const std::string& body_name) const {
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].name == body_name) return static_cast<int>(i);
  return -1;
}

std::unordered_map<std::string, int> SceneDescription::bodyIndices() const {
  std::unordered_map<std::string, int> index;
  for (std::size_t i = 0; i < bodies.size(); ++i) index.emplace(bodies[i].name, static_cast<int>(i));
  return index;
}

namespace {

/// The first key given twice in one JSON object (nlohmann::json would keep
/// the last silently), found with the parser's callback: a stack of the open
/// objects' keys and the open arrays' element counts gives the path.
class DuplicateKeyFinder {
 public:
  bool operator()(int, json::parse_event_t event, json& parsed) {
    using E = json::parse_event_t;
    const bool element = event == E::value || event == E::object_start || event == E::array_start;
    if (element && !frames_.empty() && frames_.back().array) ++frames_.back().index;
    switch (event) {
      case E::object_start: frames_.push_back(Frame{false, -1, {}, {}}); break;
      case E::array_start: frames_.push_back(Frame{true, -1, {}, {}}); break;
      case E::object_end:
      case E::array_end:
        if (!frames_.empty()) frames_.pop_back();
        break;
      case E::key: {
        Frame& f = frames_.back();
        f.key = parsed.get<std::string>();
        if (!f.keys.insert(f.key).second && duplicate_.empty()) duplicate_ = path() + f.key;
        break;
      }
      case E::value: break;
    }
    return true;
  }
  /// "bodies[0].mass", or "" when no key was repeated.
  const std::string& duplicate() const { return duplicate_; }

 private:
  struct Frame {
    bool array;
    long index;
    std::string key;
    std::set<std::string> keys;
  };
  /// The path of the innermost open object, ending in '.' (or empty).
  std::string path() const {
    std::string p;
    for (std::size_t i = 0; i + 1 < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      if (f.array)
        p += "[" + std::to_string(f.index) + "]";
      else
        p += (p.empty() ? "" : ".") + f.key;
    }
    return p.empty() ? p : p + ".";
  }
  std::vector<Frame> frames_;
  std::string duplicate_;
};

/// nlohmann's message in the reader's words: "[json.exception.parse_error.101]
/// parse error at line 3, column 7: syntax error while parsing object key -
/// invalid literal; last read: '{ab'; expected string literal" becomes "line
/// 3, column 7: invalid literal (read: '{ab'; expected string literal)", the
/// text read cut to 40 characters (a 400-digit number was echoed whole).
std::string jsonErrorText(const json::exception& e) {
  std::string what = e.what();
  if (const std::size_t tag_end = what.find("] "); what.compare(0, 1, "[") == 0 && tag_end != std::string::npos)
    what = what.substr(tag_end + 2);
  // Read by hand, not by std::regex: libstdc++'s matcher recurses once per
  // character, and a long text echoed after "last read" overflowed the stack
  // (found by fuzz_scene: 2000 carriage returns after a brace).
  const std::string overflow = "number overflow parsing '";
  if (what.size() > overflow.size() && what.compare(0, overflow.size(), overflow) == 0 && what.back() == '\'') {
    std::string number = what.substr(overflow.size(), what.size() - overflow.size() - 1);
    if (number.size() > 24) number = number.substr(0, 24) + "… (" + std::to_string(number.size()) + " characters)";
    return "the number " + number + " overflows a double";
  }
  // "parse error at line L, column C: [syntax error while parsing X - ]MESSAGE[; last read: 'READ'][REST]".
  const std::string head = "parse error at ";
  if (what.compare(0, head.size(), head) != 0) return what;
  const std::size_t colon = what.find(": ", head.size());
  if (colon == std::string::npos) return what;
  const std::string position = what.substr(head.size(), colon - head.size());
  if (position.compare(0, 5, "line ") != 0 || position.find(", column ") == std::string::npos) return what;
  std::string body = what.substr(colon + 2);
  const std::string syntax = "syntax error while parsing ";
  if (body.compare(0, syntax.size(), syntax) == 0)
    if (const std::size_t dash = body.find(" - "); dash != std::string::npos) body = body.substr(dash + 3);
  const std::size_t semicolon = body.find(';');
  const std::string message = body.substr(0, semicolon);
  std::string read, rest;
  if (semicolon != std::string::npos) {
    rest = body.substr(semicolon);
    // The text read ends at the first quote followed by ';' or the end.
    const std::string last_read = "; last read: '";
    if (rest.compare(0, last_read.size(), last_read) == 0) {
      for (std::size_t i = last_read.size(); i < rest.size(); ++i) {
        if (rest[i] == '\'' && (i + 1 == rest.size() || rest[i + 1] == ';')) {
          read = rest.substr(last_read.size(), i - last_read.size());
          rest = rest.substr(i + 1);
          break;
        }
      }
    }
  }
  if (read.size() > 40) read = read.substr(0, 40) + "…";
  if (rest.rfind("; ", 0) == 0) rest = rest.substr(2);
  std::string detail = read.empty() ? rest : "read: '" + read + "'" + (rest.empty() ? "" : "; " + rest);
  return position + ": " + message + (detail.empty() ? "" : " (" + detail + ")");
}

/// A UTF-8 byte-order mark some editors write at the start of a file.
constexpr char kUtf8Bom[] = "\xEF\xBB\xBF";

}  // namespace

SceneDescription parseScene(const std::string& text, const std::string& source, long max_bodies) {
  const std::size_t bom = text.compare(0, 3, kUtf8Bom) == 0 ? 3 : 0;
  if (text.find_first_not_of(" \t\r\n", bom) == std::string::npos)
    throw InvalidInput(source, "is empty (a scene file is a JSON object)");
  json root;
  DuplicateKeyFinder duplicates;
  try {
    root = json::parse(text.begin() + static_cast<std::ptrdiff_t>(bom), text.end(), std::ref(duplicates));
  } catch (const json::exception& e) {
    throw InvalidInput(source, "not valid JSON: " + jsonErrorText(e));
  }
  if (!duplicates.duplicate().empty())
    throw InvalidInput(source + ": " + duplicates.duplicate(), "given twice (each key may appear once per object)");
  ObjectReader r(root, "", source);
  SceneDescription scene;
  scene.source = source;
  scene.name = r.string("name");
  if (r.has("description")) scene.description = r.string("description");
  if (r.has("gravity")) scene.gravity = r.vector3("gravity");

  const json& bodies = r.array("bodies");
  if (bodies.empty()) r.fail("bodies", "a scene needs at least one body");
  if (static_cast<long>(bodies.size()) > max_bodies)
    throw limitExceeded(source + ": bodies", "bodies", static_cast<double>(bodies.size()),
                        static_cast<double>(max_bodies), "`max_bodies`");
  std::unordered_map<std::string, int> body_index;  // (linear in the bodies: chain-N has up to 1e5)
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    scene.bodies.push_back(readBody(bodies[i], static_cast<int>(i), source));
    if (!body_index.emplace(scene.bodies[i].name, static_cast<int>(i)).second)
      throw InvalidInput(source + ": bodies[" + std::to_string(i) + "].name",
                         "duplicate body name '" + scene.bodies[i].name + "'");
  }

  if (r.has("joints")) {
    const json& joints = r.array("joints");
    std::unordered_map<std::string, std::size_t> joint_index;
    for (std::size_t i = 0; i < joints.size(); ++i) {
      JointDescription j = readJoint(joints[i], static_cast<int>(i), source);
      const std::string field = source + ": joints[" + std::to_string(i) + "]";
      const auto named_before = joint_index.emplace(j.name, i);
      if (!named_before.second)
        throw InvalidInput(field + ".name", "duplicate joint name '" + j.name + "' (also joints[" +
                                                std::to_string(named_before.first->second) + "])");
      // Bodies and joints name the CSV's columns (B.x, J.x): one namespace.
      if (const auto body = body_index.find(j.name); body != body_index.end())
        throw InvalidInput(field + ".name", "'" + j.name + "' is also the name of bodies[" +
                                                std::to_string(body->second) +
                                                "]: a body and a joint would name the same CSV columns");
      std::vector<std::pair<std::string, const std::string*>> named = {{"main", &j.main},
                                                                        {"secondary", &j.secondary}};
      if (j.isGear()) named.emplace_back("carrier", &j.carrier);
      if (j.type == "differential") named.emplace_back("tertiary", &j.tertiary);
      if (j.type == "coupling") named.emplace_back("carrier_secondary", &j.carrier_secondary);
      for (const auto& nb : named)
        if (*nb.second != "ground" && !body_index.count(*nb.second))
          throw InvalidInput(field + "." + nb.first, "unknown body '" + *nb.second + "'");
      // A coupling's two joints may share a body in other roles (a common
      // parent; a follower hung from the leader's node): each joint's two
      // bodies and the two nodes must differ.
      const auto distinct = [&](std::size_t a, std::size_t b) {
        if (j.type != "coupling") return true;
        const std::string& x = named[a].first;
        const std::string& y = named[b].first;
        const auto is = [&](const char* p, const char* q) { return (x == p && y == q) || (x == q && y == p); };
        return is("main", "secondary") || is("carrier", "main") || is("carrier_secondary", "secondary");
      };
      for (std::size_t a = 0; a < named.size(); ++a)
        for (std::size_t b = 0; b < a; ++b)
          if (distinct(a, b) && *named[a].second == *named[b].second)
            throw InvalidInput(field + "." + named[a].first,
                               "joint connects body '" + *named[a].second + "' to itself (also its " +
                                   named[b].first + ")");
      scene.joints.push_back(j);
    }
  }

  if (r.has("integrator")) {
    ObjectReader ir(r.get("integrator"), "integrator", source);
    scene.has_integrator = true;
    scene.integrator.name = ir.string("name");
    scene.integrator.dt = ir.positiveNumber("dt");
    const json& obj = r.get("integrator");
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (it.key() == "name" || it.key() == "dt") continue;
      scene.integrator.options[it.key()] = ir.number(it.key());
    }
    ir.finish();
  }
  if (r.has("t_end")) {
    scene.t_end = r.positiveNumber("t_end");
    scene.has_t_end = true;
  }
  r.finish();
  return scene;
}

SceneDescription loadScene(const std::string& file_or_name, const ResourceLimits& limits,
                           const ModelImportOptions& import) {
  if (isModelFile(file_or_name)) return importModel(file_or_name, import, limits);
  std::string text;
  if (readInputFile(file_or_name, limits.max_input_bytes, &text)) {
    return parseScene(text, file_or_name, limits.max_bodies);
  }
  if (file_or_name.rfind("chain-", 0) == 0 && file_or_name.size() > 6 &&
      file_or_name.find_first_not_of("0123456789", 6) == std::string::npos && file_or_name.size() <= 15) {
    const long n = std::stol(file_or_name.substr(6));
    if (n > limits.max_bodies)
      throw limitExceeded(file_or_name, "bodies", static_cast<double>(n), static_cast<double>(limits.max_bodies),
                          "`max_bodies`");
  }
  for (const BuiltinScene& s : builtinScenes())
    if (s.name == file_or_name) return parseScene(s.json, "built-in scene '" + s.name + "'");
  std::string generated;
  if (generatedScene(file_or_name, &generated))
    return parseScene(generated, "built-in scene '" + file_or_name + "'", limits.max_bodies);
  std::string names;
  for (const BuiltinScene& s : builtinScenes()) names += (names.empty() ? "" : ", ") + s.name;
  names += ", chain-N (N = 1 ... " + std::to_string(limits.max_bodies) + ")";
  throw InvalidInput(file_or_name, "no such scene file, and no built-in scene of that name (built-in: " +
                                       names + ")");
}

}  // namespace lieflow
