#include "calibration/spring_fit.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <memory>
#include <numeric>
#include <sstream>
#include <vector>

#include <ceres/ceres.h>

#include "calibration/fit_types.hpp"
#include "calibration/shooting_grid.hpp"
#include "calibration/solver_options.hpp"
#include "calibration/spring_residuals.hpp"
#include "calibration/spring_start.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/input_number.hpp"

namespace lieflow {
namespace calibration {
namespace {

ButcherTableau tableauNamed(const std::string& name) {
  if (name == "rkmk-euler") return ButcherTableau::euler();
  if (name == "rkmk-heun") return ButcherTableau::heun();
  if (name == "rkmk3") return ButcherTableau::kutta3();
  if (name == "rkmk4") return ButcherTableau::rk4();
  throw InvalidInput("`integrator`", "'" + name +
                                         "': calibrate spring integrates the joint's model with an explicit "
                                         "RKMK tableau (rkmk-euler, rkmk-heun, rkmk3, rkmk4)");
}

/// A solve whose result cannot be used (Ceres could not evaluate the
/// residuals at the start or stopped on a numerical failure, or left
/// non-finite parameters) ends the fit with FitFailed: no covariance is
/// computed from it (that crashed inside Ceres before).
void requireUsable(const ceres::Solver::Summary& summary, const char* stage, const double* theta) {
  const bool finite = std::isfinite(summary.final_cost) && std::isfinite(theta[0]) && std::isfinite(theta[1]) &&
                      std::isfinite(theta[2]);
  if (summary.termination_type != ceres::FAILURE && summary.IsSolutionUsable() && finite) return;
  throw FitFailed(std::string("the fit failed in ") + stage +
                  ": the model could not be integrated from the start values (stiffness " + formatNumber(theta[0]) +
                  ", damping " + formatNumber(theta[1]) + ", rest angle " + formatNumber(theta[2]) +
                  "); give starts of the recording's order of magnitude (`stiffness_start`, `damping_start`) "
                  "or none (" + solverFailureReason(summary) + ")");
}


/// θ = (k, c, φ₀): k, c ≥ 0; c held if asked, φ₀ held unless fitted.
void addTheta(ceres::Problem* problem, double* theta, const SpringFitOptions& o) {
  std::vector<int> held;
  if (o.hold_damping) held.push_back(1);
  if (!o.fit_rest_angle) held.push_back(2);
  problem->AddParameterBlock(theta, 3, held.empty() ? nullptr : new ceres::SubsetManifold(3, held));
  problem->SetParameterLowerBound(theta, 0, 0.0);
  problem->SetParameterLowerBound(theta, 1, 0.0);
}

template <int N>
ceres::CostFunction* segmentCost(const SpringProblemData<N>* p, int first, int last, bool final, double w_angle,
                                 double w_rate) {
  auto* functor = new SpringSegmentCost<N>(p, first, last, final, w_angle, w_rate);
  const int m = functor->residualCount();
  if (final) return new ceres::AutoDiffCostFunction<SpringSegmentCost<N>, ceres::DYNAMIC, 3, 2 * N>(functor, m);
  return new ceres::AutoDiffCostFunction<SpringSegmentCost<N>, ceres::DYNAMIC, 3, 2 * N, 2 * N>(functor, m);
}

/// The spring fit of one joint coordinate in its stages, each a member
/// function run in order by fit(); what one stage finds, the next reads.
template <int N>
struct SpringFitter {
  SpringFitter(const SpringJoint& joint_, const SpringData& data_, const SpringFitOptions& options)
      : joint(joint_), data(data_), o(options) {}

  /// The problem's data and the least number of samples.
  void setUp() {
    n = data.size();
    ic = o.coordinate;
    free_params = 1 + (o.hold_damping ? 0 : 1) + (o.fit_rest_angle ? 1 : 0) + 2 * N;
    out.samples = n;
    if (n < std::max(o.min_samples, free_params + 2))
      throw NotIdentifiable(std::to_string(n) + " samples; at least " +
                            std::to_string(std::max(o.min_samples, free_params + 2)) + " are needed");

    p.model = &joint.model();
    p.hinge = articulated::ScalarDynamics<double>(joint.model()).groundedHinge();
    if (N == 1 && !p.hinge.valid)  // the flow's closed form divides by it
      throw InvalidInput(joint.label, "body '" + joint.body_name + "' has no inertia about the joint axis");
    p.data = &data;
    for (int i = 0; i < N; ++i) {
      p.scene_forces.stiffness[i] = joint.drives[i].stiffness;
      p.scene_forces.damping[i] = joint.drives[i].damping;
      p.scene_forces.rest_angle[i] = joint.drives[i].rest_angle;
    }
    p.coordinate = ic;
    p.tableau = tableauNamed(o.integrator);
    out.integrator = o.integrator;
  }

  /// θ = (k, c, φ₀)'s start: given, estimated from the recorded angle, or
  /// the scene's.
  void chooseStart() {
    const CoordinateDrive& scene = joint.drives[ic];
    const bool need_estimate = !o.stiffness_start || (!o.damping_start && !o.hold_damping) ||
                               (o.fit_rest_angle && !o.rest_angle_start);
    est = need_estimate ? estimateSpringStart(joint, data, ic) : SpringStart{};
    std::string from_data, from_scene, given;
    auto pick = [&](const std::optional<double>& option, double estimate, double scene_value, bool scene_ok,
                    const char* name) {
      if (option) {
        given += std::string(given.empty() ? "" : ", ") + name;
        return *option;
      }
      if (est.found) {
        from_data += std::string(from_data.empty() ? "" : ", ") + name;
        return estimate;
      }
      if (!scene_ok)
        throw NotIdentifiable("no start for the " + std::string(name) + ": " + est.why +
                              "; give `stiffness_start` and `damping_start`");
      from_scene += std::string(from_scene.empty() ? "" : ", ") + name;
      return scene_value;
    };
    theta[0] = pick(o.stiffness_start, est.stiffness, scene.stiffness, scene.stiffness > 0.0, "stiffness");
    if (o.hold_damping)
      theta[1] = o.damping_start ? *o.damping_start : scene.damping;
    else
      theta[1] = pick(o.damping_start, est.damping, scene.damping, scene.stiffness > 0.0, "damping");
    if (o.fit_rest_angle)
      theta[2] = pick(o.rest_angle_start, est.rest_angle, scene.rest_angle, true, "rest_angle");
    else
      theta[2] = o.rest_angle_start ? *o.rest_angle_start : scene.rest_angle;
    if (!(theta[0] >= 0.0) || !(theta[1] >= 0.0))
      throw InvalidInput("`stiffness_start`/`damping_start`", "starts must be >= 0");
    out.start_stiffness = theta[0];
    out.start_damping = theta[1];
    out.start_rest_angle = theta[2];
    if (!given.empty()) out.start = "given (" + given + ")";
    if (!from_data.empty())
      out.start += std::string(out.start.empty() ? "" : "; ") + "from the recorded angle (" + from_data +
                   ": lagged AR(2) recurrence, period " + formatNumber(est.period) + " s)";
    if (!from_scene.empty())
      out.start += std::string(out.start.empty() ? "" : "; ") + "the scene's (" + from_scene + ")";
    if (out.start.empty()) out.start = "given";
  }

  /// Frequencies: sub-steps, segments, defect weights; segment boundaries
  /// and initial states from local quadratics.
  void planSteps() {
    mean_angle = joint.initial_angle;
    for (int i = 0; i < N; ++i)
      if (data.has(i)) mean_angle[i] = std::accumulate(data.angle[i].begin(), data.angle[i].end(), 0.0) / n;
    double omega_max = 0.0;
    for (int i = 0; i < N; ++i) {
      const double k = (i == ic ? theta[0] : joint.drives[i].stiffness) + joint.gravityStiffness(i, mean_angle);
      const double w = std::sqrt(std::max(k, 0.0) / joint.inertiaAbout(i, mean_angle));
      if (i == ic) omega = std::max(w, est.natural_frequency);
      omega_max = std::max(omega_max, std::max(w, i == ic ? est.natural_frequency : 0.0));
    }
    duration = data.time.back() - data.time.front();
    if (!(omega > 0.0)) omega = 2.0 * kPi / duration;  // no restoring moment: one "period" per record
    const double max_interval = largestInterval(data.time);
    // The fastest motion the model predicts: the start's spring plus gravity.
    if (o.substeps == 0) requireResolved(data.source, max_interval, omega_max, "the scene and the starts give");
    // Substeps per interval in double first: an absurd start (k = 1e100) or a
    // time column in milliseconds would overflow any integer type.
    const double per_interval = o.substeps > 0 ? o.substeps
                                               : std::max(1.0, std::ceil(std::sqrt(3.0) * omega_max * max_interval /
                                                                         kStepTimesFrequency));
    const double total_substeps = per_interval * (n - 1);
    if (!(total_substeps <= static_cast<double>(o.max_substeps)))
      throw limitExceeded(data.source + ": t",
                          "integration substeps (the largest sample interval " + formatNumber(max_interval) +
                              " s at the start's frequency " + formatNumber(omega_max) +
                              " rad/s; is t in seconds, are the starts sane?)",
                          total_substeps, static_cast<double>(o.max_substeps), "`max_substeps`");
    out.substeps = static_cast<int>(per_interval);
    p.substeps = out.substeps;
    period = 2.0 * kPi / omega;
    segments = o.shooting == Shooting::kMultiple ? shootingSegments(o.segments, duration, period, n) : 1;
    out.segments = segments;
    out.shooting = shootingName(o.shooting);
    const int half_width = localFitHalfWidth(period, duration, n);

    // Segment boundaries and initial states from local quadratics.
    bound = segmentBounds(n, segments);
    state.resize(segments);
    for (int s = 0; s < segments; ++s)
      for (int i = 0; i < N; ++i) {
        const Eigen::Vector2d xv = data.has(i) ? localAngleAndRate(data, i, bound[s], half_width)
                                               : Eigen::Vector2d(joint.initial_angle[i], joint.initial_rate[i]);
        state[s][i] = xv[0];
        state[s][N + i] = xv[1];
      }
  }

  /// 1. Multiple shooting (soft continuity between the segments).
  void multipleShooting() {
    if (segments > 1) {
      ceres::Problem::Options po;
      ceres::Problem problem(po);
      addTheta(&problem, theta, o);
      for (int s = 0; s < segments; ++s) {
        const bool last = s + 1 == segments;
        ceres::CostFunction* cost =
            segmentCost<N>(&p, bound[s], bound[s + 1], last, o.continuity_weight, o.continuity_weight / omega);
        if (last)
          problem.AddResidualBlock(cost, nullptr, theta, state[s].data());
        else
          problem.AddResidualBlock(cost, nullptr, theta, state[s].data(), state[s + 1].data());
      }
      ceres::Solver::Options so;
      configureLevenbergMarquardt(&so, o, true);
      FitProgressCallback progress(o.progress, o.interrupt);
      so.callbacks.push_back(&progress);
      ceres::Solver::Summary summary;
      ceres::Solve(so, &problem, &summary);
      requireUsable(summary, "multiple shooting", theta);
      out.multiple_shooting_iterations = static_cast<int>(summary.iterations.size()) - 1;
      // The defects left by the soft continuity.
      for (int s = 0; s + 1 < segments; ++s) {
        SpringSegmentCost<N> cost(&p, bound[s], bound[s + 1], false, 1.0, 1.0);
        std::vector<double> r(cost.residualCount());
        if (cost(theta, state[s].data(), state[s + 1].data(), r.data()))
          for (int i = 0; i < N; ++i)
            out.max_continuity_defect = std::max(out.max_continuity_defect, std::abs(r[r.size() - 2 * N + 2 * i]));
      }
      message << "multiple shooting (" << segments << " segments, " << out.multiple_shooting_iterations
              << " iterations): " << solverStopMessage(summary) << "; ";
    }
  }

  /// 2. Single shooting from there.
  void singleShooting() {
    s0 = state[0];
    problem = std::make_unique<ceres::Problem>();
    addTheta(problem.get(), theta, o);
    problem->AddResidualBlock(segmentCost<N>(&p, 0, n - 1, true, 0.0, 0.0), nullptr, theta, s0.data());
    ceres::Solver::Options so;
    configureLevenbergMarquardt(&so, o, false);
    FitProgressCallback progress(o.progress, o.interrupt);
    so.callbacks.push_back(&progress);
    ceres::Solve(so, problem.get(), &summary);
    requireUsable(summary, "single shooting", theta);
    out.single_shooting_iterations = static_cast<int>(summary.iterations.size()) - 1;
    out.iterations = out.multiple_shooting_iterations + out.single_shooting_iterations;
    out.converged = summary.termination_type == ceres::CONVERGENCE;
    message << "single shooting (" << out.single_shooting_iterations << " iterations): " << solverStopMessage(summary);
    out.message = message.str();
    out.stiffness = theta[0];
    out.damping = theta[1];
    out.rest_angle = theta[2];
    out.initial_state = s0;
    m = n * data.measured();
    out.rms_residual = std::sqrt(2.0 * summary.final_cost / m);
  }

  /// Identifiability and the covariance of θ.
  void covariances() {
    double motion = 0.0;
    for (int j = 0; j < n; ++j) motion += std::pow(data.angle[ic][j] - mean_angle[ic], 2);
    motion = std::sqrt(motion / n);
    if (motion < o.min_motion_to_noise * out.rms_residual)
      throw NotIdentifiable("the joint angle barely moves: RMS " + formatNumber(motion) +
                            " rad about its mean against " + formatNumber(out.rms_residual) + " rad of residual");
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.num_threads = 1;
    ceres::Covariance covariance(co);
    const std::vector<std::pair<const double*, const double*>> blocks = {{theta, theta}};
    if (!covariance.Compute(blocks, problem.get()))
      throw NotIdentifiable("the covariance of (stiffness" + std::string(o.hold_damping ? "" : ", damping") +
                            std::string(o.fit_rest_angle ? ", rest_angle" : "") +
                            ") is rank deficient: the recorded motion does not separate them");
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> C;
    covariance.GetCovarianceBlock(theta, theta, C.data());
    const double s2 = m > free_params ? 2.0 * summary.final_cost / (m - free_params) : 0.0;
    out.covariance = s2 * Eigen::Matrix3d(C);
    out.stiffness_sigma = std::sqrt(std::max(out.covariance(0, 0), 0.0));
    out.damping_sigma = o.hold_damping ? 0.0 : std::sqrt(std::max(out.covariance(1, 1), 0.0));
    out.rest_angle_sigma = o.fit_rest_angle ? std::sqrt(std::max(out.covariance(2, 2), 0.0)) : 0.0;
    if (out.stiffness_sigma > 0.0 && out.damping_sigma > 0.0)
      out.correlation_stiffness_damping = out.covariance(0, 1) / (out.stiffness_sigma * out.damping_sigma);
    // k is determined when its σ is small against the whole restoring
    // stiffness the motion shows (spring plus gravity: a pendulum without a
    // spring determines k ≈ 0 well).
    k_gravity = joint.gravityStiffness(ic, mean_angle);
    const double k_scale = std::max(out.stiffness, out.stiffness + k_gravity);
    if (!(out.stiffness_sigma <= o.max_relative_sigma * k_scale))
      throw NotIdentifiable("the recording does not determine the stiffness: k = " + formatNumber(out.stiffness) +
                            " ± " + formatNumber(out.stiffness_sigma) +
                            " N m/rad (1 sigma) against a restoring stiffness of " + formatNumber(k_scale) +
                            " N m/rad");
  }

  /// What the numbers mean, and what the fit held fixed.
  void explain() {
    out.inertia = joint.inertiaAbout(ic, mean_angle);
    const double k_eff = out.stiffness + k_gravity;
    out.natural_frequency = std::sqrt(std::max(k_eff, 0.0) / out.inertia);
    out.damping_ratio = out.natural_frequency > 0.0 ? out.damping / (2.0 * out.inertia * out.natural_frequency) : 0.0;
    out.held_fixed.push_back("inertia of body '" + joint.body_name + "' (scene mass, inertia and anchor): " +
                             formatNumber(out.inertia) +
                             " kg m^2 about the coordinate at its mean angle; the data determine k/I and c/I");
    if (joint.weighted())
      out.held_fixed.push_back("gravity moment (scene gravity, mass and centre of mass): stiffness " +
                               formatNumber(k_gravity) + " N m/rad at the mean angle");
    if (o.hold_damping)
      out.held_fixed.push_back("damping " + formatNumber(out.damping) + " N m s/rad (" +
                               (o.damping_start ? "`damping_start`" : "scene") + ")");
    if (!o.fit_rest_angle)
      out.held_fixed.push_back("rest_angle " + formatNumber(out.rest_angle) + " rad (" +
                               (o.rest_angle_start ? "`rest_angle_start`" : "scene") + ")");
    for (int i = 0; i < N; ++i) {
      if (i != ic && (joint.drives[i].stiffness != 0.0 || joint.drives[i].damping != 0.0))
        out.held_fixed.push_back("coordinate " + std::to_string(i + 1) + " spring " +
                                 formatNumber(joint.drives[i].stiffness) + " N m/rad and dashpot " +
                                 formatNumber(joint.drives[i].damping) + " N m s/rad (scene)");
      if (joint.drives[i].moment)
        out.held_fixed.push_back("applied moment on coordinate " + std::to_string(i + 1) + " (scene)");
    }
  }

  const SpringJoint& joint;
  const SpringData& data;
  const SpringFitOptions& o;
  SpringFit out;
  SpringProblemData<N> p;
  int n = 0, ic = 0, free_params = 0, m = 0, segments = 1;
  SpringStart est;
  double theta[3] = {0.0, 0.0, 0.0};  ///< (k, c, φ₀)
  Eigen::Vector2d mean_angle = Eigen::Vector2d::Zero();
  double omega = 0.0, duration = 0.0, period = 0.0, k_gravity = 0.0;
  std::vector<int> bound;
  std::vector<Eigen::Matrix<double, 2 * N, 1>> state;  ///< per segment: (φ, φ̇) at its start
  Eigen::Matrix<double, 2 * N, 1> s0;                  ///< the single shooting's initial state
  std::ostringstream message;
  std::unique_ptr<ceres::Problem> problem;             ///< the single shooting's
  ceres::Solver::Summary summary;                      ///< the single shooting's
};

template <int N>
SpringFit fit(const SpringJoint& joint, const SpringData& data, const SpringFitOptions& o) {
  const auto clock_start = std::chrono::steady_clock::now();
  SpringFitter<N> f(joint, data, o);
  f.setUp();
  f.chooseStart();
  f.planSteps();
  f.multipleShooting();
  f.singleShooting();
  f.covariances();
  f.explain();
  f.out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  return f.out;
}

}  // namespace

const char* shootingName(Shooting s) { return s == Shooting::kMultiple ? "multiple" : "single"; }

Shooting parseShooting(const std::string& text, const std::string& field) {
  if (text == "multiple") return Shooting::kMultiple;
  if (text == "single") return Shooting::kSingle;
  throw InvalidInput(field, "'" + text + "' is not multiple or single");
}

SpringFit fitSpring(const SpringJoint& joint, const SpringData& data, const SpringFitOptions& options) {
  if (options.coordinate < 0 || options.coordinate >= joint.coordinates)
    throw InvalidInput("`coordinate`", "joint '" + joint.joint_name + "' has " + std::to_string(joint.coordinates) +
                                           " coordinate(s)");
  if (joint.coordinates == 1) return fit<1>(joint, data, options);
  return fit<2>(joint, data, options);
}

}  // namespace calibration
}  // namespace lieflow
