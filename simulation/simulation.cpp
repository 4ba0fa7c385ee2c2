/// \file
/// Scene assembly and the integrator factory of the `lieflow` command.
#include "simulation/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "integrators/registry.hpp"
#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "simulation/invariants.hpp"
#include "dynamics/maximal/multibody_scene.hpp"
#include "simulation/simulation_model.hpp"
#include "simulation/simulation_observer.hpp"
#include "simulation/stepper_table_rows.hpp"
#include "liegroup/number_text.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {

/// Relative tolerance of the consistency checks of given positions and
/// velocities against a joint.
constexpr double kConsistencyTolerance = 1e-6;


namespace {

using namespace simulation_detail;

std::string fmt(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s.precision(10);
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

std::unique_ptr<Simulation::Model> assemble(const SceneDescription& scene) {
  auto model = std::make_unique<Simulation::Model>();
  model->gravity = scene.gravity;
  for (const BodyDescription& b : scene.bodies) model->sensors.push_back(b.sensor);
  if (needsMultibody(scene)) {
    model->multibody = assembleMultibody(scene);
    const multibody::MultibodySystem& system = *model->multibody->system;
    model->invariants = InvariantSet::multibody(system.conservesAngularMomentum(),
                                                system.conservesCentreOfMassMomentum(),
                                                system.conservesEnergyBalance());
    if (articulatedCovers(scene, &model->articulated_why)) {
      model->articulated = assembleArticulated(scene);
      model->articulated->system->setConservesAngularMomentum(model->multibody->system->conservesAngularMomentum());
    }
    return model;
  }
  if (scene.bodies.size() != 1)
    throw InvalidInput(scene.source + ": bodies",
                       "this version of lieflow simulates scenes of one body (got " +
                           std::to_string(scene.bodies.size()) + ")");
  const BodyDescription& body = scene.bodies[0];
  RigidBodyParameters<double>& p = model->params;
  p.mass = body.mass;
  p.inertia = body.inertia;
  p.gravity = scene.gravity;
  const SO3d R0(body.orientation);

  if (scene.joints.size() > 1)
    throw InvalidInput(scene.source + ": joints",
                       "one body can have at most one spherical joint to ground in this version");
  if (scene.joints.size() == 1) {
    const JointDescription& j = scene.joints[0];
    const std::string field = scene.source + ": joints[0]";
    if (j.main != "ground" && j.secondary != "ground")
      throw InvalidInput(field, "a spherical joint of a single body must connect it to 'ground'");
    // Anchor on the body (body frame, from the centre of mass) and on ground (world).
    const bool body_is_secondary = j.secondary == body.name;
    const Eigen::Vector3d anchor_body = body_is_secondary ? j.anchor_secondary : j.anchor_main;
    const Eigen::Vector3d anchor_world = body_is_secondary ? j.anchor_main : j.anchor_secondary;
    p.has_pivot = true;
    p.pivot_world = anchor_world;
    p.com_from_pivot = -anchor_body;
    const Eigen::Vector3d com = anchor_world + R0 * p.com_from_pivot;
    const double length = std::max(1.0, p.com_from_pivot.norm());
    if (body.has_position && (body.position - com).norm() > kConsistencyTolerance * length)
      throw InvalidInput(scene.source + ": bodies[0].position",
                         "inconsistent with joint '" + j.name + "': the pivot puts the centre of mass at " +
                             fmt(com) + ", the file says " + fmt(body.position));
    const Eigen::Vector3d v_com = R0 * body.angular_velocity.cross(p.com_from_pivot);
    const double speed = std::max(1.0, v_com.norm());
    if (body.has_velocity && (body.velocity - v_com).norm() > kConsistencyTolerance * speed)
      throw InvalidInput(scene.source + ": bodies[0].velocity",
                         "inconsistent with joint '" + j.name + "': the pivot gives " + fmt(v_com) +
                             ", the file says " + fmt(body.velocity));
    model->rotor = true;
    model->translational_output = !body.rotation_only;
  } else if (body.rotation_only) {
    if (body.has_velocity && body.velocity.norm() > 0.0)
      throw InvalidInput(scene.source + ": bodies[0].velocity",
                         "a rotation-only body has no translational state; velocity must be zero or absent");
    model->rotor = true;
    model->translational_output = false;
    model->fixed_position = body.position;
  } else {
    model->rotor = false;
    model->translational_output = true;
  }
  if (body.spring_stiffness > 0.0) {
    if (!model->rotor)
      throw InvalidInput(scene.source + ": bodies[0].torsional_spring",
                         "a torsional spring to ground needs a rotation-only body or a pivot");
    p.spring_stiffness = body.spring_stiffness;
    p.spring_rest = SO3d(body.spring_rest);
  }
  const Eigen::Matrix3d J = model->rotor ? RotorSystem<double>(p).inertia() : p.inertia;
  model->invariants = InvariantSet::singleBody(J, p.has_pivot, p.com_from_pivot, p.gravity,
                                               p.spring_stiffness == 0.0 && !p.torque_body);
  model->rotor0.R = R0;
  model->rotor0.omega = body.angular_velocity;
  model->free0.R = R0;
  model->free0.omega = body.angular_velocity;
  model->free0.p = body.position;
  model->free0.v = body.velocity;
  return model;
}

/// The column of the table of steppers (stepper_table.hpp) a scene runs in.
SystemKind kindOf(const Simulation::Model& m, const std::string& formulation) {
  if (!m.multibody) return SystemKind::kSingleBody;
  if (formulation != "joint") return SystemKind::kMaximal;
  const articulated::ArticulatedSystem& s = *m.articulated->system;
  if (!s.hasClosures()) return SystemKind::kJointTree;
  return s.couplingRows().size() != 0 ? SystemKind::kJointCoupled : SystemKind::kJointLoops;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : " ") + n;
  return out;
}

}  // namespace

Simulation::Simulation(SceneDescription scene)
    : scene_(std::move(scene)), model_(assemble(scene_)) {}
Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

std::vector<std::string> Simulation::columns(bool imu) const {
  std::vector<std::string> cols = {"t"};
  if (model_->multibody) {
    const multibody::MultibodySystem& sys = *model_->multibody->system;
    for (int i = 0; i < sys.bodyCount(); ++i) {
      const std::string& b = scene_.bodies[i].name;
      for (const char* c : {"qw", "qx", "qy", "qz", "wx", "wy", "wz"}) cols.push_back(b + "." + c);
      if (!sys.rotationOnly(i))
        for (const char* c : {"x", "y", "z", "vx", "vy", "vz"}) cols.push_back(b + "." + c);
      if (imu)
        for (const char* c : {"ax", "ay", "az"}) cols.push_back(b + "." + c);
    }
    for (std::size_t k = 0; k < sys.model().joints.size(); ++k) {
      const std::string& j = sys.model().joints[k].name;
      const int nc = sys.coordinateCount(static_cast<int>(k));
      const JointKind kind = jointKind(sys.model().joints[k].constraint);
      if (kind == JointKind::kPrismatic)
        for (const char* c : {"x", "xdot", "force"}) cols.push_back(j + "." + c);
      else if (kind == JointKind::kFixed)
        for (const char* c : {"fx", "fy", "fz", "mx", "my", "mz"}) cols.push_back(j + "." + c);
      else if (nc == 1)
        for (const char* c : {"phi", "phidot", "moment"}) cols.push_back(j + "." + c);
      if (nc == 2)
        for (const char* c : {"phi1", "phi2", "phi1dot", "phi2dot", "moment1", "moment2"}) cols.push_back(j + "." + c);
      if (nc == 3)
        for (const char* c : {"phi1", "phi2", "phi3", "phi1dot", "phi2dot", "phi3dot", "moment1", "moment2", "moment3"})
          cols.push_back(j + "." + c);
    }
    for (const char* c : {"energy", "Lx", "Ly", "Lz", "constraint_error"}) cols.push_back(c);
    return cols;
  }
  const std::string& b = scene_.bodies[0].name;
  for (const char* c : {"qw", "qx", "qy", "qz", "wx", "wy", "wz"}) cols.push_back(b + "." + c);
  if (model_->translational_output)
    for (const char* c : {"x", "y", "z", "vx", "vy", "vz"}) cols.push_back(b + "." + c);
  if (imu)
    for (const char* c : {"ax", "ay", "az"}) cols.push_back(b + "." + c);
  for (const char* c : {"energy", "Lx", "Ly", "Lz", "constraint_error"}) cols.push_back(c);
  return cols;
}

std::vector<std::string> Simulation::invariantNames() const { return model_->invariants.names(); }

bool Simulation::hasConstraints() const { return model_->multibody != nullptr; }

bool Simulation::hasJointFormulation(std::string* why) const {
  if (!model_->multibody || model_->articulated) return true;
  if (why) *why = model_->articulated_why;
  return false;
}

std::string Simulation::defaultFormulation(const std::string& integrator) const {
  // Joint coordinates wherever they run the scene, genalpha on floating
  // trees too: at rest there its maximal form is faster (no Newton iteration
  // and a cheap KKT matrix: Solo12 5.7 against 8.5 µs per step at 2 ms), but
  // a robot in motion needs iterations, each a KLU refactorization of the
  // KKT matrix (turning at ω = (0.5, 1, 2) rad/s, joint against maximal:
  // Solo12 33 / 151 µs, ANYmal 33 / 148, Talos 120 / 711, Talos full
  // 655 / 2383, MuJoCo's humanoid 67 / 235).
  // A cell that runs only when asked for (stepper_table.hpp, notDefaultReason).
  if (!model_->multibody) return "joint";
  if (!supports(integrator, nullptr, "joint")) return "maximal";
  return jointOnlyWhenAskedFor(integrator).empty() ? "joint" : "maximal";
}

std::string Simulation::jointOnlyWhenAskedFor(const std::string& integrator) const {
  if (!model_->multibody || !model_->articulated || !findIntegrator(integrator)) return "";
  return notDefaultReason(integrator, kindOf(*model_, "joint"));
}

bool Simulation::supports(const std::string& integrator, std::string* why, const std::string& formulation_in) const {
  const IntegratorInfo* info = findIntegrator(integrator);
  if (!info) {
    if (why) *why = "unknown integrator '" + integrator + "' (see lieflow integrators)";
    return false;
  }
  if (model_->multibody && model_->multibody->has_user_loads && info->is_implicit) {
    if (why) *why = "'" + integrator + "' treats forces implicitly; loads from a program need an explicit integrator";
    return false;
  }
  const std::string formulation = formulation_in.empty() ? defaultFormulation(integrator) : formulation_in;
  if (model_->multibody && formulation == "joint" && !hasJointFormulation(why)) {
    if (why) *why = "joint coordinates cannot represent this scene: " + *why;
    return false;
  }
  const SystemKind kind = kindOf(*model_, formulation);
  const std::string none = stepperUnavailable(integrator, kind);
  if (!none.empty()) {
    if (why) {
      *why = "'" + integrator + "' is not available " + systemKindName(kind) + " (" + none +
             "; available: " + joined(steppersFor(kind)) + ")";
      if (kind != SystemKind::kSingleBody && kind != SystemKind::kMaximal &&
          stepperUnavailable(integrator, SystemKind::kMaximal).empty())
        *why += "; it runs the scene in maximal coordinates (`formulation` maximal)";
    }
    return false;
  }
  using namespace stepper_table;
  switch (kind) {
    case SystemKind::kSingleBody: return covers<SingleBody>(integrator, model_->params, why);
    case SystemKind::kMaximal: return covers<Maximal>(integrator, *model_->multibody->system, why);
    case SystemKind::kJointTree: return covers<JointTree>(integrator, *model_->articulated->system, why);
    case SystemKind::kJointCoupled: return covers<JointCoupled>(integrator, *model_->articulated->system, why);
    case SystemKind::kJointLoops: return covers<JointLoops>(integrator, *model_->articulated->system, why);
  }
  return true;
}

SimulationResult Simulation::run(const SimulationOptions& options,
                                 const std::function<void(const std::vector<double>&)>& row) const {
  const IntegratorInfo* info = findIntegrator(options.integrator);
  if (!info)
    throw InvalidInput("`integrator`", "unknown integrator '" + options.integrator +
                                           "' (see lieflow integrators)");
  if (!options.formulation.empty() && options.formulation != "maximal" && options.formulation != "joint")
    throw InvalidInput("`formulation`", "'" + options.formulation + "' is not a formulation (maximal or joint)");
  const std::string formulation = options.formulation.empty() ? defaultFormulation(options.integrator) : options.formulation;
  std::string why;
  if (model_->multibody && formulation == "joint" && !hasJointFormulation(&why))
    throw InvalidInput("`formulation`", "joint coordinates cannot represent this scene: " + why +
                                            " (run it with `formulation` maximal)");
  if (!supports(options.integrator, &why, formulation)) throw InvalidInput("`integrator`", why);
  if (!(options.dt > 0.0) || !std::isfinite(options.dt))
    throw InvalidInput(options.dt_source, "the step must be a positive number");
  if (!(options.t_end > 0.0) || !std::isfinite(options.t_end))
    throw InvalidInput(options.t_end_source, "the end time must be a positive number");
  if (options.every < 1) throw InvalidInput("`every`", "must be a positive integer");
  if (options.dt > options.t_end)
    throw InvalidInput(options.dt_source, "the step " + formatNumber(options.dt) + " is longer than the run (t_end = " +
                                              formatNumber(options.t_end) + ", " + options.t_end_source +
                                              "): give a step no longer than t_end");
  // The step count, checked before it is converted to an integer (t_end/dt
  // can exceed every integer type, or the run would take years).
  const double steps_needed = std::ceil(options.t_end / options.dt * (1.0 - 1e-9));
  if (steps_needed > static_cast<double>(options.max_steps))
    throw limitExceeded(options.dt_source + " " + formatNumber(options.dt) + " with " + options.t_end_source + " " +
                            formatNumber(options.t_end),
                        info->is_adaptive ? "output rows" : "steps", steps_needed,
                        static_cast<double>(options.max_steps), "`max_steps`");
  for (const auto& kv : options.integrator_options) {
    const std::string field = options.command_line_options.count(kv.first)
                                  ? "`options` " + kv.first
                                  : scene_.source + ": integrator." + kv.first;
    const IntegratorOption* spec = info->option(kv.first);
    if (!spec) throw InvalidInput(field, "unknown option for integrator '" + info->name + "'");
    const std::string why = spec->check(kv.second);
    if (!why.empty()) throw InvalidInput(field, why + " (" + spec->meaning + ")");
  }
  const std::vector<std::string> columns = this->columns(options.imu);

  const Model& m = *model_;
  const SystemKind kind = kindOf(m, formulation);
  SimulationResult result;
  try {
    using stepper_table::runStepper;
    if (kind == SystemKind::kMaximal)
      result = runStepper(stepper_table::Maximal{}, m, *m.multibody->system, m.multibody->y0, options, columns, row);
    else if (kind != SystemKind::kSingleBody)
      result = runArticulated(m, kind, options, columns, row);
    else if (m.rotor)
      result = runStepper(stepper_table::SingleBody{}, m, RotorSystem<double>(m.params), m.rotor0, options, columns, row);
    else
      result = runStepper(stepper_table::SingleBody{}, m, FreeBodySystem<double>(m.params), m.free0, options, columns,
                          row);
  } catch (const InvalidInput& e) {
    // A stepper's constructor names a bare option (rho_inf): the scene's
    // integrator.OPTION. A field that names its place already (a file's, an
    // option such as `dt`, a program's load such as torques['arm']) passes as it is; other
    // bare fields are the scene's.
    const std::string& field = e.field();
    const auto& known = info->options;
    if (std::any_of(known.begin(), known.end(), [&](const IntegratorOption& o) { return o.name == field; }))
      throw InvalidInput(scene_.source + ": integrator." + field, e.reason());
    if (field.find(':') != std::string::npos || field.rfind("`", 0) == 0 || field.find("['") != std::string::npos)
      throw;
    throw InvalidInput(scene_.source + ": " + field, e.reason());
  }
  result.integrator = options.integrator;
  result.formulation = m.multibody ? formulation : "joint";
  result.dt = options.dt;
  result.implicit = info->is_implicit;
  // A figure that overflowed (an energy of 1e300 against one of 1e-300) is
  // not reported as a number: the run fails saying which.
  std::vector<std::pair<std::string, double>> figures = {{"energy drift", result.energy_drift},
                                                         {"momentum drift", result.momentum_drift},
                                                         {"constraint error", result.constraint_error}};
  figures.insert(figures.end(), result.invariants.begin(), result.invariants.end());
  for (const auto& f : figures)
    if (!result.failed && !std::isfinite(f.second)) {
      result.failed = true;
      result.failure = "the " + f.first + " is not a finite number (" + formatNumber(f.second) +
                       "): the scene's magnitudes exceed double precision";
    }
  return result;
}

}  // namespace lieflow
