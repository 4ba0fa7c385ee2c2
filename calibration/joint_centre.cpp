#include "calibration/joint_centre.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "calibration/fit_types.hpp"
#include "calibration/solver_options.hpp"
#include "calibration/rate_derivative.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// Solver stopping tolerances: far below the noise of any accelerometer.
constexpr double kFunctionTolerance = 1e-14;
constexpr double kParameterTolerance = 1e-14;
constexpr int kMaxCentreIterations = 200;
/// The gauge row's weight against the data rows' Jacobian scale.
constexpr double kGaugeWeight = 1e4;
/// Smallest eigenvalue of the information matrix, relative to the largest,
/// for the centre to count as determined.
constexpr double kMinInformation = 1e-10;

template <typename T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

/// The norms of the residual are √(‖v‖² + ε²) with this ε [m/s²], far below
/// any accelerometer's noise: ‖v‖ has no derivative at v = 0, where a
/// recording with zero specific force (no gravity, a body at rest or in free
/// fall) puts the solve's start o = 0, and the solve would stop there on
/// non-finite Jacobians.
constexpr double kNormSmoothing = 1e-9;

/// e = ‖f₁ + ω̇₁ × o₁ + ω₁ × (ω₁ × o₁)‖ − ‖f₂ + ω̇₂ × o₂ + ω₂ × (ω₂ × o₂)‖.
struct CentreResidual {
  Eigen::Vector3d f1, w1, a1, f2, w2, a2;

  template <typename T>
  static T smoothNorm(const Vec3<T>& v) {
    using std::sqrt;
    return sqrt(v.squaredNorm() + T(kNormSmoothing * kNormSmoothing));
  }

  template <typename T>
  static Vec3<T> moved(const Eigen::Vector3d& f, const Eigen::Vector3d& w, const Eigen::Vector3d& a,
                       const Vec3<T>& o) {
    const Vec3<T> wt = w.cast<T>();
    return f.cast<T>() + a.cast<T>().cross(o) + wt.cross(wt.cross(o));
  }

  template <typename T>
  bool operator()(const T* o1_data, const T* o2_data, T* r) const {
    const Eigen::Map<const Vec3<T>> o1(o1_data), o2(o2_data);
    r[0] = smoothNorm<T>(moved<T>(f1, w1, a1, Vec3<T>(o1))) - smoothNorm<T>(moved<T>(f2, w2, a2, Vec3<T>(o2)));
    return true;
  }
};

/// weight · (o₁·j₁ + o₂·j₂): the hinge's gauge (file comment).
struct HingeGauge {
  Eigen::Vector3d j1, j2;
  double weight;
  template <typename T>
  bool operator()(const T* o1, const T* o2, T* r) const {
    T s = T(0.0);
    for (int i = 0; i < 3; ++i) s += T(j1[i]) * o1[i] + T(j2[i]) * o2[i];
    r[0] = T(weight) * s;
    return true;
  }
};

constexpr int kWindow = kCentreWindow;
/// Lags of the residuals' autocovariance in the sandwich covariance:
/// neighbouring residuals share rates through the window.
constexpr int kLags = 2 * kWindow + 1;



void requireCentreData(const JointSamples& samples) {
  for (const BodySamples* b : {&samples.main, &samples.secondary}) {
    if (!b->hasAngularVelocity())
      throw InvalidInput(samples.source, "the joint centre needs the gyroscopes of body '" + b->name + "' (" +
                                             b->name + ".wx, " + b->name + ".wy, " + b->name + ".wz)");
    if (!b->hasSpecificForce())
      throw InvalidInput(samples.source, "the joint centre needs the accelerometers of body '" + b->name + "' (" +
                                             b->name + ".ax, " + b->name + ".ay, " + b->name + ".az)");
    if (b->specific_force.size() != samples.time.size())
      throw InvalidInput(samples.source, "body '" + b->name + "' has a different number of accelerometer samples than t");
  }
  const std::size_t n = samples.time.size();
  if (n < 2 * kWindow + 12)
    throw NotIdentifiable("the joint centre needs at least " + std::to_string(2 * kWindow + 12) +
                          " samples (the recording has " + std::to_string(n) + ")");
}

/// The residual of interior sample k (k − kWindow ≥ 0, k + kWindow < n).
CentreResidual residualAt(const JointSamples& samples, std::size_t k) {
  return CentreResidual{samples.main.specific_force[k],
                        samples.main.angular_velocity[k],
                        rateDerivative(samples.time, samples.main.angular_velocity, k),
                        samples.secondary.specific_force[k],
                        samples.secondary.angular_velocity[k],
                        rateDerivative(samples.time, samples.secondary.angular_velocity, k)};
}

/// Least squares of the norm residuals (and the hinge gauge when the axes
/// are given) from o = 0; o1, o2 receive the solution.
ceres::Solver::Summary solveCentre(const JointSamples& samples, const Eigen::Vector3d* axis_main,
                                   const Eigen::Vector3d* axis_secondary, double* o1, double* o2) {
  const std::size_t n = samples.time.size();
  for (int i = 0; i < 3; ++i) o1[i] = o2[i] = 0.0;
  ceres::Problem::Options problem_options;
  ceres::Problem problem(problem_options);
  double scale = 0.0;  // RMS of |ω|² + |ω̇|: the data rows' Jacobian scale [1/s²]
  for (std::size_t k = kWindow; k + kWindow < n; ++k) {
    const CentreResidual c = residualAt(samples, k);
    scale += std::pow(c.w1.squaredNorm() + c.a1.norm(), 2) + std::pow(c.w2.squaredNorm() + c.a2.norm(), 2);
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<CentreResidual, 1, 3, 3>(new CentreResidual(c)),
                             nullptr, o1, o2);
  }
  const int rows = static_cast<int>(n) - 2 * kWindow;
  scale = std::sqrt(scale / (2.0 * rows));
  if (axis_main && axis_secondary) {
    const double weight = kGaugeWeight * std::max(scale, 1.0) * std::sqrt(static_cast<double>(rows));
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<HingeGauge, 1, 3, 3>(
                                 new HingeGauge{axis_main->normalized(), axis_secondary->normalized(), weight}),
                             nullptr, o1, o2);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.function_tolerance = kFunctionTolerance;
  options.parameter_tolerance = kParameterTolerance;
  options.max_num_iterations = kMaxCentreIterations;
  options.logging_type = ceres::SILENT;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable())
    throw FitFailed("the joint-centre solve failed: " + solverFailureReason(summary));
  return summary;
}

}  // namespace

CentreForces centreSpecificForces(const JointSamples& samples, const Eigen::Vector3d& o1, const Eigen::Vector3d& o2) {
  requireCentreData(samples);
  CentreForces out;
  const std::size_t n = samples.time.size();
  out.first = kWindow;
  for (std::size_t k = kWindow; k + kWindow < n; ++k) {
    const CentreResidual c = residualAt(samples, k);
    out.main.push_back(CentreResidual::moved<double>(c.f1, c.w1, c.a1, o1));
    out.secondary.push_back(CentreResidual::moved<double>(c.f2, c.w2, c.a2, o2));
  }
  return out;
}

void solveJointCentre(const JointSamples& samples, Eigen::Vector3d* anchor_main, Eigen::Vector3d* anchor_secondary) {
  requireCentreData(samples);
  double o1[3], o2[3];
  solveCentre(samples, nullptr, nullptr, o1, o2);
  *anchor_main = Eigen::Vector3d(o1[0], o1[1], o1[2]);
  *anchor_secondary = Eigen::Vector3d(o2[0], o2[1], o2[2]);
}

JointCentreFit fitJointCentre(const JointSamples& samples, const Eigen::Vector3d* axis_main,
                              const Eigen::Vector3d* axis_secondary, int correlation_samples) {
  const int lags = std::max(kLags, correlation_samples);
  requireCentreData(samples);
  const std::size_t n = samples.time.size();
  double o1[3], o2[3];
  const ceres::Solver::Summary summary = solveCentre(samples, axis_main, axis_secondary, o1, o2);
  const bool hinge = axis_main && axis_secondary;
  const int rows = static_cast<int>(n) - 2 * kWindow;

  JointCentreFit fit;
  fit.anchor_main = Eigen::Vector3d(o1[0], o1[1], o1[2]);
  fit.anchor_secondary = Eigen::Vector3d(o2[0], o2[1], o2[2]);
  fit.samples = rows;
  fit.iterations = static_cast<int>(summary.iterations.size()) - 1;
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  fit.message = solverStopMessage(summary);
  // The data rows' residual sum of squares (the gauge row holds to rounding).
  double rss = 0.0;
  for (std::size_t k = kWindow; k + kWindow < n; ++k) {
    const CentreResidual c = residualAt(samples, k);
    double r = 0.0;
    c(o1, o2, &r);
    rss += r * r;
  }
  fit.rms_residual = std::sqrt(rss / rows);
  const int p = 6 - (hinge ? 1 : 0);
  if (rows <= p) throw NotIdentifiable("too few samples for the six coordinates of the joint centre");

  // Sandwich covariance (Newey & West 1987): B⁻¹ M B⁻¹ with B = Σ g gᵀ (and
  // the gauge row), M = Σ_k Σ_|l|≤L (1 − |l|/(L+1)) e_k e_{k+l} g_k g_{k+l}ᵀ,
  // g_k = ∂e_k/∂(o₁, o₂): the residuals' own scatter, correlated over the
  // rates' window, and any misfit of the model, instead of an assumed noise.
  using Jet = ceres::Jet<double, 6>;
  std::vector<double> e;
  std::vector<Eigen::Matrix<double, 6, 1>> g;
  e.reserve(rows);
  g.reserve(rows);
  Jet jo1[3], jo2[3];
  for (int i = 0; i < 3; ++i) {
    jo1[i] = Jet(o1[i], i);
    jo2[i] = Jet(o2[i], 3 + i);
  }
  for (std::size_t k = kWindow; k + kWindow < n; ++k) {
    const CentreResidual c = residualAt(samples, k);
    Jet r;
    c(jo1, jo2, &r);
    e.push_back(r.a);
    g.push_back(r.v);
  }
  Eigen::Matrix<double, 6, 6> B = Eigen::Matrix<double, 6, 6>::Zero(), M = Eigen::Matrix<double, 6, 6>::Zero();
  for (int k = 0; k < rows; ++k) {
    B.noalias() += g[k] * g[k].transpose();
    for (int l = -lags; l <= lags; ++l) {
      const int m = k + l;
      if (m < 0 || m >= rows) continue;
      const double w = 1.0 - std::abs(l) / static_cast<double>(lags + 1);
      M.noalias() += (w * e[k] * e[m]) * g[k] * g[m].transpose();
    }
  }
  if (hinge) {
    Eigen::Matrix<double, 6, 1> gauge;
    gauge << axis_main->normalized(), axis_secondary->normalized();
    B.noalias() += (B.trace() / 6.0) * kGaugeWeight * gauge * gauge.transpose();
  }
  const char* hint =
      "the centre shows in the accelerometers only when the bodies turn about varied axes and their "
      "rates change";
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(B);
  if (!(eig.eigenvalues().minCoeff() > kMinInformation * eig.eigenvalues().maxCoeff()))
    throw NotIdentifiable(std::string("the joint centre's information matrix is singular; ") + hint);
  const Eigen::Matrix<double, 6, 6> Binv = eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() *
                                           eig.eigenvectors().transpose();
  fit.covariance = (static_cast<double>(rows) / (rows - p)) * Binv * M * Binv;
  fit.sigma_main = std::sqrt(fit.covariance.topLeftCorner<3, 3>().trace());
  fit.sigma_secondary = std::sqrt(fit.covariance.bottomRightCorner<3, 3>().trace());
  if (!std::isfinite(fit.sigma_main) || !std::isfinite(fit.sigma_secondary))
    throw NotIdentifiable(std::string("the joint centre's σ is not finite; ") + hint);
  return fit;
}

}  // namespace calibration
}  // namespace lieflow
