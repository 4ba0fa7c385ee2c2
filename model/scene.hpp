/// \file
/// The description of a scene as read from a JSON scene file (format in
/// README "Scene file"; contract in ../shared/DESIGN.md): bodies, joints,
/// gravity, the integrator and the end time. It is plain data, validated on
/// reading; `assemble*` functions turn it into systems that integrators step.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "model/import/import_options.hpp"
#include "model/time_function.hpp"
#include "model/resource_limits.hpp"
#include "model/visual_shape.hpp"

namespace lieflow {

/// One rigid body. Inertia is about the centre of mass in body axes.
struct BodyDescription {
  std::string name;
  double mass = 0.0;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();
  /// A rotation-only body has no translational state (its centre of mass
  /// stays where it is, or turns about a pivot).
  bool rotation_only = false;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< body frame
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          ///< world frame
  bool has_position = false;
  bool has_velocity = false;
  /// Optional isotropic torsional spring to ground ("torsional_spring":
  /// {"stiffness": k, "rest_orientation": [w, x, y, z]}): body torque
  /// −k log(R_rest⁻¹ R). Rotation-only bodies and bodies on a pivot only.
  double spring_stiffness = 0.0;
  /// The inertial sensor's point ("sensor"), body axes, from the centre of
  /// mass: where `simulate --imu` evaluates the specific force B.ax, B.ay, B.az.
  Eigen::Vector3d sensor = Eigen::Vector3d::Zero();
  Eigen::Quaterniond spring_rest = Eigen::Quaterniond::Identity();
  /// What it looks like (model files; body axes from the centre of mass):
  /// only the replay reads it.
  std::vector<VisualShape> visuals;
};

/// Force elements and drive of one joint coordinate (revolute φ, universal
/// φ₁ or φ₂, prismatic x): `spring` {stiffness, rest_angle} (prismatic:
/// rest_position), `damper` {damping}, `moment` (prismatic: `force`) and
/// `prescribed` (time functions). A prismatic coordinate's values are
/// lengths [m], its stiffness N/m, its damping N s/m.
struct CoordinateDescription {
  double stiffness = 0.0;
  double rest_angle = 0.0;  ///< rest angle [rad] or, prismatic, rest position [m]
  double damping = 0.0;
  std::optional<TimeFunction> moment;
  std::optional<TimeFunction> prescribed;
};

/// A gear node's local axes (r, s[, t]) in its body's frame.
struct NodeAxesDescription {
  Eigen::Vector3d r = Eigen::Vector3d::UnitX();
  Eigen::Vector3d s = Eigen::Vector3d::UnitY();
  bool has_t = false;
  Eigen::Vector3d t = Eigen::Vector3d::UnitZ();
};

/// One joint. `main`/`secondary` are body names; "ground" is the world.
/// Anchors and axes are in the frame of the body they belong to (the suffix
/// of their names says which).
struct JointDescription {
  std::string name;
  std::string type;
  std::string main;
  std::string secondary;
  Eigen::Vector3d anchor_main = Eigen::Vector3d::Zero();
  Eigen::Vector3d anchor_secondary = Eigen::Vector3d::Zero();
  /// revolute: axis_main (and optionally axis_secondary; else R_b⁻¹ R_a a_main
  /// at t = 0); universal: axis1_main, axis2_secondary.
  Eigen::Vector3d axis_main = Eigen::Vector3d::UnitZ();
  bool has_axis_secondary = false;
  Eigen::Vector3d axis_secondary = Eigen::Vector3d::UnitZ();
  /// universal: the second axis passes through anchor_secondary, apart from
  /// the first through anchor_main (`"offset": true`; MuJoCo's two hinges of
  /// one body at two points): the distance between the anchors is held.
  bool offset = false;
  /// gimbal: the second and third hinge axes (main frame, at zero angles;
  /// the first is axis_main).
  Eigen::Vector3d axis2_main = Eigen::Vector3d::UnitY();
  Eigen::Vector3d axis3_main = Eigen::Vector3d::UnitZ();
  /// Joint angles at t = 0 (revolute: [0]; universal: two; gimbal: three). Default 0.
  std::array<double, 3> initial_angles{{0.0, 0.0, 0.0}};
  /// revolute, prismatic: [0]; universal, gimbal: [i] = φ_{i+1} (suffix "1", "2", "3").
  std::array<CoordinateDescription, 3> coordinates;
  /// gear, rack_pinion, differential, coupling: ratio α, carrier body (default
  /// "ground"), third node (differential: `tertiary`) and node axes
  /// (axes_main, axes_secondary, axes_tertiary).
  double ratio = 0.0;
  std::string carrier = "ground";
  /// coupling: the secondary node's carrier (its joint's other body; JSON
  /// "carrier_secondary", default `carrier`, then the main node's).
  std::string carrier_secondary;
  std::string tertiary;
  NodeAxesDescription axes_main, axes_secondary, axes_tertiary;

  /// coupling: whether each node slides (a prismatic joint to the carrier)
  /// or turns (a revolute one) along its axis (axes_main.r,
  /// axes_secondary.r: "axis_main", "axis_secondary" in the scene file;
  /// "motion_main", "motion_secondary": "turn" or "slide").
  bool slide_main = false, slide_secondary = false;

  /// gear, rack_pinion, differential or coupling (velocity rows between a
  /// carrier and nodes).
  bool isGear() const {
    return type == "gear" || type == "rack_pinion" || type == "differential" || type == "coupling";
  }
};

/// The integrator a scene asks for: a name of `lieflow integrators`, a step
/// and named numeric options (e.g. rho_inf for genalpha).
struct IntegratorDescription {
  std::string name;
  double dt = 0.0;
  std::map<std::string, double> options;
};

/// Loads a program supplies as functions of time and state (the Python
/// module's callables; the JSON scene format has none). A scene with any runs
/// as a multibody system and with the explicit integrators only (their
/// forces are evaluated where the stages need them; lgvi and genalpha treat
/// forces implicitly and are refused).
struct UserLoads {
  /// Torque on a body, body frame [N m], about its centre of mass, from the
  /// time and the body's orientation q (body to world), position p (world),
  /// body angular velocity ω and velocity v (world).
  using BodyTorque = std::function<Eigen::Vector3d(double t, const Eigen::Quaterniond& q, const Eigen::Vector3d& p,
                                                   const Eigen::Vector3d& omega, const Eigen::Vector3d& v)>;
  /// Moment on joint coordinate `coordinate` (0 or 1) [N m], from the time
  /// and the coordinate's angle and rate; it acts like the scene's `moment`.
  using JointMoment = std::function<double(double t, int coordinate, double phi, double phidot)>;
  std::map<std::string, BodyTorque> body_torques;  ///< by body name
  std::map<std::string, JointMoment> joint_moments;  ///< by joint name
  bool empty() const { return body_torques.empty() && joint_moments.empty(); }
};

struct SceneDescription {
  std::string name;
  /// Where it came from ("path/to/file.json" or "built-in scene 'NAME'"),
  /// used to prefix error messages.
  std::string source;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  std::vector<BodyDescription> bodies;
  std::vector<JointDescription> joints;
  bool has_integrator = false;
  IntegratorDescription integrator;
  bool has_t_end = false;
  double t_end = 0.0;
  /// One line on what the scene shows (built-in scenes).
  std::string description;
  /// Loads given as functions by a program (none from a scene file).
  UserLoads user_loads;
  /// What a model importer changed, one sentence each ("ignored limits:
  /// limit of joint 'elbow' (line 6)" for what --ignore let it leave out,
  /// "renamed joint ..."); the commands print them to stderr.
  std::vector<std::string> import_notes;
  /// Shapes fixed to the world (a model file's base or floor geoms), world frame.
  std::vector<VisualShape> ground_visuals;

  /// Index of the body with this name, or -1 (a linear search; code that
  /// looks up every joint's bodies builds bodyIndices() once instead).
  int bodyIndex(const std::string& body_name) const;
  /// Body name → index, for all bodies.
  std::unordered_map<std::string, int> bodyIndices() const;
};

/// Whether `text` is valid UTF-8 (no stray continuation byte, no truncated
/// or overlong sequence, no surrogate, nothing beyond U+10FFFF): the JSON and
/// CSV files lieflow writes are UTF-8, and a name that is not would make them
/// unreadable (the JSON writer refuses it).
inline bool validUtf8(const std::string& text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned char c = s[i];
    const int extra = c < 0x80 ? 0 : (c & 0xE0) == 0xC0 ? 1 : (c & 0xF0) == 0xE0 ? 2 : (c & 0xF8) == 0xF0 ? 3 : -1;
    if (extra < 0 || i + static_cast<std::size_t>(extra) >= n) return false;
    std::uint32_t code = extra == 0 ? c : c & (0x3F >> extra);
    for (int k = 1; k <= extra; ++k) {
      if ((s[i + k] & 0xC0) != 0x80) return false;
      code = (code << 6) | (s[i + k] & 0x3F);
    }
    static constexpr std::uint32_t kSmallest[] = {0, 0x80, 0x800, 0x10000};
    if (code < kSmallest[extra] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return false;
    i += static_cast<std::size_t>(extra) + 1;
  }
  return true;
}

/// Why `name` cannot name a body or joint, or an empty string: the names
/// become CSV column prefixes ("B.qw") and JSON keys, so a comma, a quote, a
/// line break or another control character would break the files written,
/// and bytes that are not UTF-8 would make them unreadable.
inline std::string columnNameProblem(const std::string& name) {
  if (!validUtf8(name)) return "is not valid UTF-8 text";
  for (const char c : name) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (c == ',' || c == '"' || u < 0x20 || u == 0x7f)
      return "holds a character that would break the CSV columns named after it (a comma, a quote or a control "
             "character such as a line break)";
  }
  return std::string();
}

/// Parses and validates a scene from JSON text (one leading UTF-8 byte-order
/// mark is skipped, as by the recording reader). Throws InvalidInput whose
/// field is "SOURCE: FIELD" (e.g. "top.json: bodies[0].inertia") and whose
/// reason says what is wrong; a key given twice in one object and more bodies
/// than `max_bodies` are errors too.
SceneDescription parseScene(const std::string& json_text, const std::string& source,
                            long max_bodies = kMaxBodies);

/// Reads SCENE: a model file (a path ending in .xml or .urdf: MJCF or URDF,
/// model/import/model_import.hpp, leaving out what `import` allows), a JSON
/// file if such a file exists, else a built-in scene of that name. Throws
/// InvalidInput naming the file (or name) and the reason. Reads at most
/// limits.max_input_bytes (an endless stream such as /dev/zero is refused
/// once past it) and accepts at most limits.max_bodies bodies.
SceneDescription loadScene(const std::string& file_or_name, const ResourceLimits& limits = ResourceLimits(),
                           const ModelImportOptions& import = ModelImportOptions());

/// The built-in scenes: name, one-line description and JSON text.
struct BuiltinScene {
  std::string name;
  std::string description;
  std::string json;
};
const std::vector<BuiltinScene>& builtinScenes();

/// Scenes generated from their name (`chain-N`, N ≥ 1; loadScene holds N to
/// the body limit): writes the JSON text and returns true, or returns false
/// for other names.
bool generatedScene(const std::string& name, std::string* json);

}  // namespace lieflow
