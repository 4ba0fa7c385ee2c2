/// \file
/// The joint centre from gyroscopes and accelerometers
/// (calibration/joint_centre.hpp) on recordings simulated with sensors away
/// from the bodies' centres of mass (`simulate --imu` rows): two rotation-only
/// bodies joined at their common centre of mass — the `hinge-pair` motion, and
/// the same pair on a spherical joint — under gravity, so the true centre
/// from each sensor is −s in body axes (on the hinge: the point of the axis
/// closest to the two sensors). Exact data give it to the accuracy of the
/// rates' central differences; 50 noisy trials (new motion, new noise) check
/// that σ is honest as the axis fits' σ are (honesty_test.cpp's criteria).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "app/recording_noise.hpp"
#include "calibration/fit_types.hpp"
#include "calibration/joint_centre.hpp"
#include "calibration/spherical_fit.hpp"
#include "calibration/wobble_check.hpp"
#include "calibration/low_pass.hpp"
#include "calibration_test_helpers.hpp"
#include "model/scene.hpp"
#include "simulation/simulation.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace calibration {
namespace {

const Eigen::Vector3d kSensorUpper(0.05, -0.03, 0.08), kSensorLower(-0.04, 0.06, 0.02);
const Eigen::Vector3d kAxisUpper = Eigen::Vector3d(0.0, 0.6, 0.8);
/// The lower body starts turned 0.6 rad about x (hinge-pair's geometry).
const Eigen::Quaterniond kLowerStart(0.9553364891256060, 0.2955202066613396, 0.0, 0.0);

/// hinge-pair's two bodies with gravity and sensors, the given joint type and
/// initial rates.
SceneDescription pairScene(const std::string& type, const Eigen::Vector3d& w_upper, const Eigen::Vector3d& w_lower) {
  std::ostringstream s;
  s.precision(17);
  s << R"({"name": "pair", "gravity": [0, 0, -9.81], "bodies": [
      {"name": "upper", "mass": 1.0, "inertia": [0.02, 0.05, 0.065], "rotation_only": true,
       "angular_velocity": [)"
    << w_upper.x() << ", " << w_upper.y() << ", " << w_upper.z() << R"(], "sensor": [0.05, -0.03, 0.08]},
      {"name": "lower", "mass": 1.0, "inertia": [0.012, 0.03, 0.035], "rotation_only": true,
       "orientation": [0.9553364891256060, 0.2955202066613396, 0, 0], "angular_velocity": [)"
    << w_lower.x() << ", " << w_lower.y() << ", " << w_lower.z() << R"(], "sensor": [-0.04, 0.06, 0.02]}],
    "joints": [{"name": "j", "type": ")"
    << type << R"(", "main": "upper", "secondary": "lower", "anchor_main": [0, 0, 0],
       "anchor_secondary": [0, 0, 0])"
    << (type == "revolute" ? R"(, "axis_main": [0, 0.6, 0.8], "spring": {"stiffness": 0.4},
       "moment": {"type": "sine", "amplitude": 0.05, "frequency": 0.7})"
                           : "")
    << "}]}";
  return parseScene(s.str(), "pair.json");
}

/// The recording of `scene` (rkmk4, h = 1e-3, every 10th step: 100 Hz),
/// with the given noise, as the two bodies' samples.
/// A sensor wobbling on soft tissue, added to the recorded rows: each
/// gyroscope reads `rate` rad/s and each accelerometer `acc` m/s² more, at
/// 10–20 Hz about a random axis (neither is a motion of the joint).
struct Wobble {
  double rate = 0.0, acc = 0.0;
  double hz[4] = {0, 0, 0, 0}, phase[4] = {0, 0, 0, 0};
  Eigen::Vector3d axis[4];
  Wobble() = default;
  Wobble(double r, double a, std::mt19937& gen) : rate(r), acc(a) {
    std::uniform_real_distribution<double> f(10.0, 20.0), p(0.0, 2.0 * M_PI);
    std::normal_distribution<double> normal;
    for (int i = 0; i < 4; ++i) {
      hz[i] = f(gen);
      phase[i] = p(gen);
      axis[i] = Eigen::Vector3d(normal(gen), normal(gen), normal(gen)).normalized();
    }
  }
  Eigen::Vector3d at(int i, double t) const {
    return (i % 2 ? acc : rate) * std::sin(2.0 * M_PI * hz[i] * t + phase[i]) * axis[i];
  }
};

JointSamples record(const SceneDescription& scene, double seconds, const app::NoiseOptions& noise,
                    const Wobble& wobble = Wobble()) {
  const Simulation sim(scene);
  SimulationOptions o;
  o.integrator = "rkmk4";
  o.formulation = "joint";
  o.dt = 1e-3;
  o.t_end = seconds;
  o.every = 10;
  o.imu = true;
  const std::vector<std::string> columns = sim.columns(true);
  app::RecordingNoise perturb(columns, noise);
  JointSamples joint;
  joint.source = "simulated pair";
  joint.main.name = "upper";
  joint.secondary.name = "lower";
  auto column = [&](const std::string& name) {
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name) return static_cast<int>(i);
    ADD_FAILURE() << "no column " << name;
    return 0;
  };
  const int w1 = column("upper.wx"), a1 = column("upper.ax"), w2 = column("lower.wx"), a2 = column("lower.ax");
  const SimulationResult r = sim.run(o, [&](const std::vector<double>& clean) {
    std::vector<double> row = clean;
    if (noise.any()) perturb.apply(&row);
    const double t = row[0];
    joint.time.push_back(t);
    joint.main.angular_velocity.push_back(Eigen::Vector3d(row[w1], row[w1 + 1], row[w1 + 2]) + wobble.at(0, t));
    joint.main.specific_force.push_back(Eigen::Vector3d(row[a1], row[a1 + 1], row[a1 + 2]) + wobble.at(1, t));
    joint.secondary.angular_velocity.push_back(Eigen::Vector3d(row[w2], row[w2 + 1], row[w2 + 2]) + wobble.at(2, t));
    joint.secondary.specific_force.push_back(Eigen::Vector3d(row[a2], row[a2 + 1], row[a2 + 2]) + wobble.at(3, t));
  });
  EXPECT_FALSE(r.failed) << r.failure;
  return joint;
}

/// The hinge's axis in the lower body's frame, and the true centres from the
/// sensors: −s moved along the axis to the point closest to both sensors.
struct HingeTruth {
  Eigen::Vector3d j1, j2, o1, o2;
  HingeTruth() {
    j1 = kAxisUpper.normalized();
    j2 = kLowerStart.toRotationMatrix().transpose() * j1;
    const double lambda = -((-kSensorUpper).dot(j1) + (-kSensorLower).dot(j2)) / 2.0;
    o1 = -kSensorUpper + lambda * j1;
    o2 = -kSensorLower + lambda * j2;
  }
};

TEST(CalibJointCentre, HingeFromExactData) {
  const HingeTruth truth;
  const JointSamples joint =
      record(pairScene("revolute", Eigen::Vector3d(2.0, -1.0, 1.5), Eigen::Vector3d(-1.0, 2.5, 0.5)), 10.0, {});
  const JointCentreFit fit = fitJointCentre(joint, &truth.j1, &truth.j2);
  EXPECT_TRUE(fit.converged) << fit.message;
  EXPECT_LT((fit.anchor_main - truth.o1).norm(), 2e-4) << fit.anchor_main.transpose() << " vs "
                                                       << truth.o1.transpose();
  EXPECT_LT((fit.anchor_secondary - truth.o2).norm(), 2e-4) << fit.anchor_secondary.transpose();
  EXPECT_NEAR(fit.anchor_main.dot(truth.j1) + fit.anchor_secondary.dot(truth.j2), 0.0, 1e-9);  // the gauge
}

TEST(CalibJointCentre, SphericalFromExactData) {
  const JointSamples joint =
      record(pairScene("spherical", Eigen::Vector3d(2.0, -1.0, 1.5), Eigen::Vector3d(-1.0, 2.5, 0.5)), 10.0, {});
  const JointCentreFit fit = fitJointCentre(joint, nullptr, nullptr);
  EXPECT_TRUE(fit.converged) << fit.message;
  EXPECT_LT((fit.anchor_main + kSensorUpper).norm(), 2e-4) << fit.anchor_main.transpose();
  EXPECT_LT((fit.anchor_secondary + kSensorLower).norm(), 2e-4) << fit.anchor_secondary.transpose();
}

TEST(CalibJointCentre, NeedsBothAccelerometers) {
  JointSamples joint =
      record(pairScene("spherical", Eigen::Vector3d(2.0, -1.0, 1.5), Eigen::Vector3d(-1.0, 2.5, 0.5)), 1.0, {});
  joint.secondary.specific_force.clear();
  EXPECT_THROW(fitJointCentre(joint, nullptr, nullptr), InvalidInput);
}

/// The sensors' noise of these tests: gyroscopes 0.01 rad/s, accelerometers
/// 0.05 m/s², drawn from `seed`.
app::NoiseOptions sensorNoise(unsigned long long seed) {
  app::NoiseOptions noise;
  noise.gyro = 0.01;
  noise.acc = 0.05;
  noise.seed = seed;
  return noise;
}

/// 50 trials, random initial rates (2-4 rad/s per axis), gyroscope noise
/// 0.01 rad/s and accelerometer noise 0.05 m/s² at 100 Hz for 10 s (also
/// under the sanitizers: on 3 s recordings σ is too small, mean (error/σ)²
/// 1.7–2.3 on the spherical joint, calibration/README.md): errors within 3σ in
/// all but 2, mean (error/σ)² in [0.5, 1.6].
/// With `wobble`, the sensors wobble (Wobble: 1 rad/s and 2 m/s²) and the
/// signals are low-passed at 5 Hz first, as `calibrate spherical --low-pass 5`.
void expectHonest(const std::string& type, unsigned seed, double seconds = 10.0, bool wobble = false) {
  const HingeTruth truth;
  const bool hinge = type == "revolute";
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> rate(-4.0, 4.0);
  int covered[2] = {0, 0}, answered = 0, refused = 0;
  double ratio_sq[2] = {0.0, 0.0};
  constexpr int kTrials = 50;
  for (int t = 0; t < kTrials; ++t) {
    const Eigen::Vector3d w1(rate(gen), rate(gen), rate(gen)), w2(rate(gen), rate(gen), rate(gen));
    const app::NoiseOptions noise = sensorNoise(gen());
    const JointSamples recorded =
        record(pairScene(type, w1, w2), seconds, noise, wobble ? Wobble(1.0, 2.0, gen) : Wobble());
    LowPassFilter filter;
    const JointSamples joint = wobble ? lowPassed(recorded, 5.0, "--low-pass", &filter) : recorded;
    const int correlated = wobble ? lowPassCorrelationSamples(filter) : 0;
    JointCentreFit fit;
    try {
      fit = hinge ? fitJointCentre(joint, &truth.j1, &truth.j2, correlated)
                  : fitJointCentre(joint, nullptr, nullptr, correlated);
    } catch (const NotIdentifiable&) {
      ++refused;
      continue;
    }
    ++answered;
    const Eigen::Vector3d o1 = hinge ? truth.o1 : Eigen::Vector3d(-kSensorUpper);
    const Eigen::Vector3d o2 = hinge ? truth.o2 : Eigen::Vector3d(-kSensorLower);
    const double error[2] = {(fit.anchor_main - o1).norm(), (fit.anchor_secondary - o2).norm()};
    const double sigma[2] = {fit.sigma_main, fit.sigma_secondary};
    for (int b = 0; b < 2; ++b) {
      covered[b] += error[b] <= 3.0 * sigma[b];
      ratio_sq[b] += error[b] * error[b] / (sigma[b] * sigma[b]);
    }
  }
  std::printf("%s%s: answered %d, refused %d, within 3 sigma %d / %d, mean (error/sigma)^2 %.2f / %.2f\n",
              type.c_str(), wobble ? " (wobbling, low-passed at 5 Hz)" : "", answered, refused, covered[0], covered[1],
              answered ? ratio_sq[0] / answered : 0.0, answered ? ratio_sq[1] / answered : 0.0);
  EXPECT_LE(refused, 2);
  ASSERT_GT(answered, 0);
  for (int b = 0; b < 2; ++b) {
    SCOPED_TRACE(b == 0 ? "anchor_main" : "anchor_secondary");
    ratio_sq[b] /= answered;
    EXPECT_GE(covered[b], answered - 2) << "within 3 sigma in " << covered[b] << " of " << answered;
    EXPECT_GT(ratio_sq[b], 0.5) << "sigma too large: mean (error/sigma)^2 = " << ratio_sq[b];
    EXPECT_LT(ratio_sq[b], 1.6) << "sigma too small: mean (error/sigma)^2 = " << ratio_sq[b];
    testing::Test::RecordProperty("mean_error_over_sigma_squared_" + type + (b ? "_secondary" : "_main"),
                                  std::to_string(ratio_sq[b]));
  }
}

TEST(CalibJointCentre, HingeSigmaIsHonest) { expectHonest("revolute", 51); }
TEST(CalibJointCentre, SphericalSigmaIsHonest) { expectHonest("spherical", 52); }
/// Wobbling sensors, low-passed at 5 Hz (measured in the note of calibration/README.md).
TEST(CalibJointCentre, LowPassedWobblingSensorsAreHonest) {
  expectHonest("spherical", 53, 10.0, true);
  expectHonest("revolute", 54, 10.0, true);
}

/// No flag (issue 31): `calibrate spherical` finds the wobble by itself
/// (fitSpherical: low-passed at kWobbleCutoffHz, saying so), the answers are
/// as honest as with --low-pass 5 above, and on 40 s recordings the check
/// across the quarters (10 s each: kMinCentreSegmentSamples) runs and agrees;
/// a recording without a wobble stays unfiltered, and 10 s are too short
/// for the check (it says so).
TEST(CalibJointCentre, SphericalDefaultsFilterAWobbleAndCheckTheQuarters) {
  std::mt19937 gen(55);
  std::uniform_real_distribution<double> rate(-4.0, 4.0);
  constexpr int kTrials = test::kSanitized ? 2 : 12;
  int covered = 0, agreed = 0;
  double ratio_sq = 0.0;
  for (int t = 0; t < kTrials; ++t) {
    const Eigen::Vector3d w1(rate(gen), rate(gen), rate(gen)), w2(rate(gen), rate(gen), rate(gen));
    const app::NoiseOptions noise = sensorNoise(gen());
    const JointSamples recorded = record(pairScene("spherical", w1, w2), 40.0, noise, Wobble(1.0, 2.0, gen));
    const SphericalFit fit = fitSpherical(recorded);
    EXPECT_EQ(fit.low_pass_hz, kWobbleCutoffHz);
    EXPECT_NE(fit.low_pass_reason.find("wobbles on soft tissue"), std::string::npos) << fit.low_pass_reason;
    agreed += fit.model_check.ran && !fit.model_check.disagree;
    const double error[2] = {(fit.centre.anchor_main + kSensorUpper).norm(),
                             (fit.centre.anchor_secondary + kSensorLower).norm()};
    const double sigma[2] = {fit.centre.sigma_main, fit.centre.sigma_secondary};
    for (int b = 0; b < 2; ++b) {
      covered += error[b] <= 3.0 * sigma[b];
      ratio_sq += error[b] * error[b] / (sigma[b] * sigma[b]) / 2.0;
    }
  }
  ratio_sq /= kTrials;
  std::printf("spherical, wobbling, no flag: within 3 sigma %d / %d anchors, mean (error/sigma)^2 %.2f, model check "
              "agreeing in %d of %d\n",
              covered, 2 * kTrials, ratio_sq, agreed, kTrials);
  // (Statistics over 12 recordings; the sanitized run's 2 only run the code.)
  if (!test::kSanitized) {
    EXPECT_GE(covered, 2 * kTrials - 3);
    EXPECT_GT(ratio_sq, 0.4);
    EXPECT_LT(ratio_sq, 1.8);
    EXPECT_GE(agreed, kTrials - 2);
  }
  const app::NoiseOptions noise = sensorNoise(9);
  const SphericalFit plain =
      fitSpherical(record(pairScene("spherical", Eigen::Vector3d(1, -2, 3), Eigen::Vector3d(-3, 1, 2)), 10.0, noise));
  EXPECT_EQ(plain.low_pass_hz, 0.0);
  EXPECT_NE(plain.low_pass_reason.find("no gyroscope wobbles"), std::string::npos) << plain.low_pass_reason;
  EXPECT_FALSE(plain.model_check.ran);
  EXPECT_NE(plain.model_check.note.find("fewer than 4 segments of 1000"), std::string::npos) << plain.model_check.note;
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
