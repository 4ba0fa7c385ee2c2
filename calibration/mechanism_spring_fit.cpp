#include "calibration/mechanism_spring_fit.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <memory>
#include <array>
#include <sstream>

#include <ceres/ceres.h>
#include <Eigen/Eigenvalues>

#include "calibration/fit_types.hpp"
#include "calibration/solver_options.hpp"
#include "calibration/mechanism_flow.hpp"
#include "calibration/mechanism_spring_residuals.hpp"
#include "calibration/mechanism_spring_start.hpp"
#include "calibration/shooting_grid.hpp"
#include "calibration/spring_data.hpp"
#include "calibration/unit_axis.hpp"
#include "dynamics/joint_space/articulated_scene.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/input_number.hpp"

namespace lieflow {
namespace calibration {
namespace {

ceres::CostFunction* segmentCost(const MechanismShared* p, int first, int last, bool final, double w_angle,
                                 double w_rate, int theta_size) {
  auto* functor = new MechanismSegmentCost(p, first, last, final, w_angle, w_rate);
  const int residuals = functor->residualCount();
  auto* cost = new ceres::DynamicAutoDiffCostFunction<MechanismSegmentCost, 4>(functor);
  cost->AddParameterBlock(theta_size);
  for (std::size_t a = 0; a < p->axis_bodies.size(); ++a) cost->AddParameterBlock(3);
  for (int segment = 0; segment < (final ? 1 : 2); ++segment) {  // its state, then the next's
    cost->AddParameterBlock(p->stateSize());
    for (int k = 0; k < p->rotations; ++k) cost->AddParameterBlock(4);
  }
  cost->SetNumResiduals(residuals);
  return cost;
}

void requireUsable(const ceres::Solver::Summary& summary, const char* stage) {
  if (summary.termination_type != ceres::FAILURE && summary.IsSolutionUsable() && std::isfinite(summary.final_cost))
    return;
  throw FitFailed(std::string("the mechanism spring fit failed in ") + stage +
                  ": the model could not be integrated from the start values (the scene's springs and dashpots); "
                  "give the scene values of the recording's order of magnitude (" + solverFailureReason(summary) + ")");
}

/// The mechanism spring fit in its stages, each a member function run in
/// order by fitMechanismSprings; what one stage finds, the next reads.
struct MechanismFitter {
  MechanismFitter(const SceneDescription& scene_, const Recording& recording_, const MechanismSpringOptions& options)
      : scene(scene_), recording(recording_), o(options) {}

  /// The tree in joint coordinates, and the coordinates to fit: those with a
  /// spring or a dashpot in the scene (with --fit-axis, the axes of sprung
  /// revolute joints too).
  void collectCoordinates() {
    std::string why;
    if (!articulatedCovers(scene, &why)) throw InvalidInput("`scene`", "the mechanism spring fit: " + why);
    tree = assembleArticulated(scene);
    const articulated::ArticulatedModel& model = tree->system->model();
    requireMechanismSupported(model, "`scene`");
    p.model = &model;
    p.coordinates = model.scalar_coordinates;
    p.rotations = model.rotations;
    p.dofs = model.dofs();
    p.time = recording.time;
    column_of.assign(static_cast<std::size_t>(p.coordinates), std::string());
    for (int i = 0; i < model.bodyCount(); ++i) {
      const articulated::ArticulatedBody& b = model.bodies[static_cast<std::size_t>(i)];
      if (b.coordinates() == 0) continue;  // a spherical joint: nothing sprung, no angle
      const std::string& joint = scene.joints[static_cast<std::size_t>(b.scene_joint)].name;
      for (int k = 0; k < b.coordinates(); ++k) {
        const CoordinateDrive& d = model.drives[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
        const int j = b.q_begin + k;
        p.scene_forces.stiffness.push_back(d.stiffness);
        p.scene_forces.damping.push_back(d.damping);
        p.scene_forces.rest_angle.push_back(d.rest_angle);
        column_of[static_cast<std::size_t>(j)] =
            joint + (b.kind == articulated::JointKind::kUniversal ? ".phi" + std::to_string(k + 1) : ".phi");
        if (d.stiffness > 0.0 || d.damping > 0.0) {
          p.fitted.push_back(j);
          CoordinateSpring c;
          c.joint = joint;
          c.coordinate = k + 1;
          c.stiffness_fitted = d.stiffness > 0.0;
          c.damping_fitted = d.damping > 0.0;
          c.start_stiffness = d.stiffness;
          c.start_damping = d.damping;
          c.rest_angle = d.rest_angle;
          fitted.push_back(c);
          if (o.fit_axis && b.kind == articulated::JointKind::kRevolute) {
            p.axis_bodies.push_back(i);
            axis_of.push_back(fitted.size() - 1);
          }
        }
      }
    }
    if (p.fitted.empty())
      throw InvalidInput("`scene`", scene.source + ": no joint coordinate has a spring or a dashpot to fit");
  }

  /// What the recording holds for the fit (every joint angle, or every
  /// body's gyroscopes), the samples and the free parameters.
  void selectData() {
    const articulated::ArticulatedModel& model = *p.model;
    for (int j = 0; j < p.coordinates; ++j) {
      const std::vector<double>* c = recording.column(column_of[static_cast<std::size_t>(j)]);
      p.angles.push_back(c);
      if (!c) missing_angles.push_back(column_of[static_cast<std::size_t>(j)]);
    }
    for (int i = 0; i < model.bodyCount(); ++i) {
      const std::string& name = model.names[static_cast<std::size_t>(i)];
      const BodySamples* b = recording.body(name);
      p.rates.push_back(b && b->hasAngularVelocity() ? &b->angular_velocity : nullptr);
      if (!p.rates.back()) missing_rates.push_back(name + ".wx," + name + ".wy," + name + ".wz");
    }
    MechanismData data = o.data;
    std::string spherical;  // a body on a spherical joint: no angle column says where it turns
    for (int i = 0; i < model.bodyCount() && spherical.empty(); ++i)
      if (model.bodies[static_cast<std::size_t>(i)].kind == articulated::JointKind::kSpherical)
        spherical = model.names[static_cast<std::size_t>(i)];
    if (!spherical.empty() && data == MechanismData::kAngles)
      throw InvalidInput("`data`", "angles: body '" + spherical +
                                       "' turns on a spherical joint, which no angle column records: fit from "
                                       "every body's gyroscopes (`data` gyroscopes)");
    if (!spherical.empty() && data == MechanismData::kAuto && !missing_rates.empty())
      throw InvalidInput(recording.source, "body '" + spherical +
                                               "' turns on a spherical joint, which no angle column records: the "
                                               "mechanism spring fit needs every body's gyroscopes (missing: " +
                                               list(missing_rates) + ")");
    if (data == MechanismData::kAuto) {
      if (missing_angles.empty() && spherical.empty()) data = MechanismData::kAngles;
      else if (missing_rates.empty()) data = MechanismData::kGyroscopes;
      else
        throw InvalidInput(recording.source, "the mechanism spring fit needs every joint angle (missing: " +
                                                 list(missing_angles) + ") or every body's gyroscopes (missing: " +
                                                 list(missing_rates) + ")");
    }
    if (data == MechanismData::kAngles && !missing_angles.empty())
      throw InvalidInput(recording.source, "`data` angles: missing columns " + list(missing_angles));
    if (data == MechanismData::kGyroscopes && !missing_rates.empty())
      throw InvalidInput(recording.source, "`data` gyroscopes: missing columns " + list(missing_rates));
    p.gyroscopes = data == MechanismData::kGyroscopes;
    out.data = mechanismDataName(data);
    out.residual_unit = p.gyroscopes ? "rad/s" : "rad";
    n = static_cast<int>(p.time.size());
    out.samples = n;
    int spring_parameters = 0;
    for (const CoordinateSpring& c : fitted)
      spring_parameters += c.stiffness_fitted + c.damping_fitted + (o.fit_rest_angle && c.stiffness_fitted);
    free_parameters =
        spring_parameters + 2 * static_cast<int>(p.axis_bodies.size()) + p.stateSize() + 3 * p.rotations;
    if (o.fit_axis && p.axis_bodies.empty())
      throw InvalidInput("`fit_axis`", "no sprung or damped revolute joint whose axis could be fitted");
    // The axes, started at the scene's (unit, on the sphere).
    axes.resize(p.axis_bodies.size());
    for (std::size_t a = 0; a < axes.size(); ++a) {
      const Eigen::Vector3d v = model.bodies[static_cast<std::size_t>(p.axis_bodies[a])].axis1.normalized();
      axes[a] = {v.x(), v.y(), v.z()};
    }
    if (n < std::max(o.min_samples, free_parameters + 2))
      throw NotIdentifiable(std::to_string(n) + " samples; at least " +
                            std::to_string(std::max(o.min_samples, free_parameters + 2)) + " are needed");
  }

  /// The springs and dashpots the solve starts from: the scene's, or
  /// inverse dynamics of the recorded (or integrated) angles.
  void chooseStart() {
    const articulated::ArticulatedModel& model = *p.model;
    start_forces = p.scene_forces;
    out.start = "the scene's springs and dashpots";
    // The angles the start reads: recorded, or integrated from the gyroscopes
    // (from the scene's initial angles) when only rates are recorded.
    std::vector<std::vector<double>> integrated;
    std::vector<const std::vector<double>*> start_angles = p.angles;
    std::string angles_from = "the recorded angles";
    if (!missing_angles.empty() && missing_rates.empty() &&
        anglesFromGyroscopes(model, tree->y0.q, p.time, p.rates, &integrated)) {
      for (std::size_t j = 0; j < integrated.size(); ++j) start_angles[j] = &integrated[j];
      angles_from = "the angles integrated from the gyroscopes (from the scene's initial angles)";
    }
    // (A spherical joint's rotation is in no angle: its inverse dynamics has no motion to read.)
    const bool have_angles = p.rotations == 0 &&
                             std::find(start_angles.begin(), start_angles.end(), nullptr) == start_angles.end();
    if (o.start == MechanismStartFrom::kInverseDynamics && !have_angles)
      throw InvalidInput("`start`", p.rotations > 0
                                        ? "inverse-dynamics reads the joint angles, and a spherical joint's rotation "
                                          "is in none: start from the scene (`start` scene)"
                                        : "inverse-dynamics needs every joint angle in the recording, or every "
                                          "body's gyroscopes on revolute and universal joints (missing: " +
                                              list(missing_angles) + ")");
    if (o.start == MechanismStartFrom::kInverseDynamics ||
        (o.start == MechanismStartFrom::kAuto && have_angles && n >= kInverseDynamicsMinSamples)) {
      std::vector<StartCoordinate> coordinates;
      for (std::size_t f = 0; f < fitted.size(); ++f)
        coordinates.push_back({p.fitted[f], fitted[f].stiffness_fitted, fitted[f].damping_fitted,
                               o.fit_rest_angle && fitted[f].stiffness_fitted, fitted[f].rest_angle});
      const MechanismStart s = inverseDynamicsStart(model, p.time, start_angles, coordinates);
      std::string kept;
      for (std::size_t f = 0; f < fitted.size(); ++f) {
        CoordinateSpring& c = fitted[f];
        const std::string name = c.joint + "." + std::to_string(c.coordinate);
        if (c.stiffness_fitted && s.stiffness_usable[f]) {
          c.start_stiffness = s.stiffness[f];
          c.rest_angle = s.rest_angle[f];
        } else if (c.stiffness_fitted) {
          kept += (kept.empty() ? "" : "; ") + name + " stiffness (estimate " + formatNumber(s.stiffness[f]) + ")";
        }
        if (c.damping_fitted && s.damping_usable[f])
          c.start_damping = s.damping[f];
        else if (c.damping_fitted)
          kept += (kept.empty() ? "" : "; ") + name + " damping (estimate " + formatNumber(s.damping[f]) + ")";
        const std::size_t j = static_cast<std::size_t>(p.fitted[f]);
        start_forces.stiffness[j] = c.start_stiffness;
        start_forces.damping[j] = c.start_damping;
        start_forces.rest_angle[j] = c.rest_angle;
      }
      out.start = "inverse dynamics of " + angles_from + " (local cubics over +-" + std::to_string(s.half_width) +
                  " samples)";
      if (!kept.empty()) out.start_note = "not positive, left at the scene's value: " + kept;
    }
  }

  /// Sub-steps per sample interval and the multiple-shooting segments, from
  /// the start model's fastest frequency.
  void planSteps() {
    const articulated::ArticulatedModel& model = *p.model;
    omega = fastestFrequency(model, start_forces, tree->y0);  // (the fit's state type in double)
    duration = p.time.back() - p.time.front();
    const double max_interval = largestInterval(p.time);
    if (o.substeps == 0) requireResolved(recording.source, max_interval, omega, "of the scene's model");
    const double per_interval =
        o.substeps > 0 ? o.substeps : std::max(1.0, std::ceil(omega * max_interval / kMechanismStepTimesFrequency));
    if (!(per_interval * (n - 1) <= static_cast<double>(o.max_substeps)))
      throw limitExceeded(recording.source + ": t", "integration substeps", per_interval * (n - 1),
                          static_cast<double>(o.max_substeps), "`max_substeps`");
    p.substeps = static_cast<int>(per_interval);
    out.substeps = p.substeps;
    period = omega > 0.0 ? 2.0 * kPi / omega : duration;
    segments = shootingSegments(o.segments, duration, period, n);
    out.segments = segments;
  }

  /// θ's start and each segment's initial state: local fits of the angles,
  /// or the scene's initial state advanced by the start model.
  void startStates() {
    const articulated::ArticulatedModel& model = *p.model;
    theta_size = 3 * static_cast<int>(p.fitted.size());
    theta.assign(static_cast<std::size_t>(theta_size), 0.0);
    for (std::size_t f = 0; f < p.fitted.size(); ++f) {
      theta[3 * f] = fitted[f].start_stiffness;
      theta[3 * f + 1] = fitted[f].start_damping;
      theta[3 * f + 2] = fitted[f].rest_angle;
    }
    bound = segmentBounds(n, segments);
    state.assign(static_cast<std::size_t>(segments), Eigen::VectorXd(p.stateSize()));
    rotation.assign(static_cast<std::size_t>(segments),
                    std::vector<std::array<double, 4>>(static_cast<std::size_t>(p.rotations)));
    if (!p.gyroscopes) {  // (no spherical joint: u = q̇)
      SpringData angles;  // localAngleAndRate reads one coordinate at a time
      angles.time = p.time;
      const int half_width = localFitHalfWidth(period, duration, n);
      for (int j = 0; j < p.coordinates; ++j) {
        angles.angle[0] = *p.angles[static_cast<std::size_t>(j)];
        for (int s = 0; s < segments; ++s) {
          const Eigen::Vector2d xv = localAngleAndRate(angles, 0, bound[s], half_width);
          state[s][j] = xv[0];
          state[s][p.coordinates + j] = xv[1];
        }
      }
    } else {
      // Only rates recorded: the scene's initial state, advanced by the start
      // model to each segment's first sample.
      MechanismDynamics<double> dynamics(model);
      const MechanismFlow<double> flow(&dynamics, start_forces);
      const RkmkStepper<MechanismState<double>> stepper = mechanismStepper<double>();
      MechanismState<double> y = tree->y0;
      int s = 0;
      for (int i = 0; i < n; ++i) {
        if (s < segments && i == bound[s]) {
          state[s] << y.q, y.u;
          for (int k = 0; k < p.rotations; ++k) {
            const Eigen::Quaterniond& w = y.N[static_cast<std::size_t>(k)].quaternion();
            rotation[s][static_cast<std::size_t>(k)] = {w.w(), w.x(), w.y(), w.z()};
          }
          ++s;
        }
        if (i + 1 == n) break;
        const double h = (p.time[i + 1] - p.time[i]) / p.substeps;
        for (int m = 0; m < p.substeps; ++m) y = stepper.step(flow, p.time[i] + m * h, y, h);
      }
    }
  }

  /// Multiple shooting, then single shooting from there; the covariance.
  void solve() {
    const auto addAxes = [&](ceres::Problem* problem) {
      for (std::array<double, 3>& a : axes) problem->AddParameterBlock(a.data(), 3, new ceres::SphereManifold<3>());
    };
    // A segment's blocks: its state (q, u), then a unit quaternion per spherical joint.
    const auto addRotations = [&](ceres::Problem* problem, int segment) {
      for (std::array<double, 4>& w : rotation[static_cast<std::size_t>(segment)])
        problem->AddParameterBlock(w.data(), 4, new ceres::QuaternionManifold());
    };
    const auto blocksOf = [&](int segment, bool with_next) {
      std::vector<double*> blocks = {theta.data()};
      for (std::array<double, 3>& a : axes) blocks.push_back(a.data());
      for (int s = segment; s <= segment + (with_next ? 1 : 0); ++s) {
        blocks.push_back(state[static_cast<std::size_t>(s)].data());
        for (std::array<double, 4>& w : rotation[static_cast<std::size_t>(s)]) blocks.push_back(w.data());
      }
      return blocks;
    };
    const auto addTheta = [&](ceres::Problem* problem) {
      std::vector<int> held;
      for (std::size_t f = 0; f < p.fitted.size(); ++f) {
        if (!fitted[f].stiffness_fitted) held.push_back(static_cast<int>(3 * f));
        if (!fitted[f].damping_fitted) held.push_back(static_cast<int>(3 * f + 1));
        if (!o.fit_rest_angle || !fitted[f].stiffness_fitted) held.push_back(static_cast<int>(3 * f + 2));
      }
      problem->AddParameterBlock(theta.data(), theta_size,
                                 held.empty() ? nullptr : new ceres::SubsetManifold(theta_size, held));
      for (std::size_t f = 0; f < p.fitted.size(); ++f) {
        problem->SetParameterLowerBound(theta.data(), static_cast<int>(3 * f), 0.0);
        problem->SetParameterLowerBound(theta.data(), static_cast<int>(3 * f + 1), 0.0);
      }
    };
    ceres::Solver::Options so;
    configureLevenbergMarquardt(&so, o, true);
    FitProgressCallback progress(o.progress, o.interrupt);
    so.callbacks.push_back(&progress);

    // --- 1. Multiple shooting ----------------------------------------------------
    if (segments > 1) {
      ceres::Problem problem;
      addTheta(&problem);
      addAxes(&problem);
      const double w_rate = o.continuity_weight / std::max(omega, 2.0 * kPi / duration);
      for (int s = 0; s < segments; ++s) addRotations(&problem, s);
      for (int s = 0; s < segments; ++s) {
        const bool last = s + 1 == segments;
        ceres::CostFunction* cost =
            segmentCost(&p, bound[s], bound[s + 1], last, o.continuity_weight, w_rate, theta_size);
        problem.AddResidualBlock(cost, nullptr, blocksOf(s, !last));
      }
      ceres::Solver::Summary summary;
      ceres::Solve(so, &problem, &summary);
      requireUsable(summary, "multiple shooting");
      out.iterations += static_cast<int>(summary.iterations.size()) - 1;
    }

    // --- 2. Single shooting and the covariance ----------------------------------
    ceres::Problem problem;
    addTheta(&problem);
    addAxes(&problem);
    addRotations(&problem, 0);
    problem.AddResidualBlock(segmentCost(&p, 0, n - 1, true, 0.0, 0.0, theta_size), nullptr, blocksOf(0, false));
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    requireUsable(summary, "single shooting");
    out.iterations += static_cast<int>(summary.iterations.size()) - 1;
    out.converged = summary.termination_type == ceres::CONVERGENCE;
    out.message = solverStopMessage(summary);
    const int m = n * p.perSample();
    out.rms_residual = std::sqrt(2.0 * summary.final_cost / m);
    const int p_free = free_parameters;
    if (m <= p_free) throw NotIdentifiable("as many parameters as recorded values");
    const double s2 = 2.0 * summary.final_cost / (m - p_free);
    covariances(&problem, s2);
  }

  /// θ's and the axes' σ from the covariance of the last solve, scaled by s².
  void covariances(ceres::Problem* problem_ptr, double s2) {
    ceres::Problem& problem = *problem_ptr;
    const articulated::ArticulatedModel& model = *p.model;
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.num_threads = 1;
    // Gyroscopes read body-axis rates, which do not change when a subtree on
    // a spherical joint to the ground is turned as a whole about the vertical
    // through the joint (about any axis without weight): those directions of
    // its start rotation are the problem's null space, dropped from the
    // pseudo-inverse (θ is orthogonal to them).
    co.null_space_rank = unobservableTurns(*p.model);
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> pairs = {{theta.data(), theta.data()}};
    for (std::array<double, 3>& a : axes) pairs.emplace_back(a.data(), a.data());
    if (!covariance.Compute(pairs, &problem))
      throw NotIdentifiable("the springs' covariance is rank deficient: the recorded motion does not separate them");
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> C(theta_size, theta_size);
    covariance.GetCovarianceBlock(theta.data(), theta.data(), C.data());
    out.covariance = s2 * Eigen::MatrixXd(C);
    for (std::size_t f = 0; f < p.fitted.size(); ++f) {
      CoordinateSpring& c = fitted[f];
      c.stiffness = theta[3 * f];
      c.damping = theta[3 * f + 1];
      c.rest_angle = theta[3 * f + 2];
      c.stiffness_sigma = std::sqrt(out.covariance(3 * f, 3 * f));
      c.damping_sigma = std::sqrt(out.covariance(3 * f + 1, 3 * f + 1));
      c.rest_angle_sigma =
          o.fit_rest_angle && c.stiffness_fitted ? std::sqrt(out.covariance(3 * f + 2, 3 * f + 2)) : 0.0;
      if (!std::isfinite(c.stiffness_sigma) || !std::isfinite(c.damping_sigma) || !std::isfinite(c.rest_angle_sigma))
        throw NotIdentifiable("the σ of joint '" + c.joint + "' is not finite");
    }
    for (std::size_t a = 0; a < axes.size(); ++a) {
      Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Ca;
      covariance.GetCovarianceBlock(axes[a].data(), axes[a].data(), Ca.data());
      CoordinateSpring& c = fitted[axis_of[a]];
      c.axis_fitted = true;
      c.axis = Eigen::Vector3d(axes[a][0], axes[a][1], axes[a][2]);
      c.axis_secondary = model.bodies[static_cast<std::size_t>(p.axis_bodies[a])].R_ref.transpose() * c.axis;
      // Ambient covariance of a unit vector: its trace is the mean squared angle.
      c.axis_sigma_deg = std::sqrt(s2 * Ca.trace()) * kRadToDeg;
      if (!std::isfinite(c.axis_sigma_deg))
        throw NotIdentifiable("the σ of joint '" + c.joint + "''s axis is not finite");
    }
  }

  static std::string list(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  }

  const SceneDescription& scene;
  const Recording& recording;
  const MechanismSpringOptions& o;
  std::unique_ptr<ArticulatedScene> tree;
  MechanismShared p;
  MechanismSpringFit out;
  std::vector<std::string> column_of;       ///< per coordinate: its angle's column
  std::vector<CoordinateSpring> fitted;
  std::vector<std::size_t> axis_of;         ///< per fitted axis: its coordinate in `fitted`
  std::vector<std::string> missing_angles, missing_rates;
  int n = 0, free_parameters = 0;
  std::vector<std::array<double, 3>> axes;  ///< fitted axes, unit
  MechanismForces<double> start_forces;
  double omega = 0.0, duration = 0.0, period = 0.0;
  int segments = 1, theta_size = 0;
  std::vector<double> theta;                ///< (k, c, φ₀) per fitted coordinate
  std::vector<int> bound;
  std::vector<Eigen::VectorXd> state;       ///< per segment: (q, u) at its start
  /// per segment: each spherical joint's rotation at its start, (w, x, y, z)
  std::vector<std::vector<std::array<double, 4>>> rotation;
};

}  // namespace

const char* mechanismDataName(MechanismData d) {
  switch (d) {
    case MechanismData::kAngles: return "angles";
    case MechanismData::kGyroscopes: return "gyroscopes";
    case MechanismData::kAuto: break;
  }
  return "auto";
}

MechanismData parseMechanismData(const std::string& text, const std::string& field) {
  for (MechanismData d : {MechanismData::kAuto, MechanismData::kAngles, MechanismData::kGyroscopes})
    if (text == mechanismDataName(d)) return d;
  throw InvalidInput(field, "unknown data '" + text + "' (auto, angles, gyroscopes)");
}

MechanismStartFrom parseMechanismStart(const std::string& text, const std::string& field) {
  if (text == "auto") return MechanismStartFrom::kAuto;
  if (text == "scene") return MechanismStartFrom::kScene;
  if (text == "inverse-dynamics") return MechanismStartFrom::kInverseDynamics;
  throw InvalidInput(field, "unknown start '" + text + "' (auto, scene, inverse-dynamics)");
}

MechanismSpringFit fitMechanismSprings(const SceneDescription& scene, const Recording& recording,
                                       const MechanismSpringOptions& o) {
  const auto clock_start = std::chrono::steady_clock::now();
  MechanismFitter fit(scene, recording, o);
  fit.collectCoordinates();
  fit.selectData();
  fit.chooseStart();
  fit.planSteps();
  fit.startStates();
  fit.solve();
  MechanismSpringFit out = std::move(fit.out);
  out.coordinates = fit.fitted;
  out.held_fixed = {"the bodies' masses and inertias", "the joints' geometry", "gravity"};
  if (!o.fit_rest_angle) out.held_fixed.push_back("the rest angles (the scene's)");
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  return out;
}

}  // namespace calibration
}  // namespace lieflow
