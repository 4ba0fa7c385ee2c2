// The hinge estimators against the Cramér–Rao bound, and what accelerometers
// and gyroscope biases do (papers/hinge-axis-identification/, section
// "Estimators, the Cramér–Rao bound, accelerometers, biases and wobbling
// sensors"). On random hinge
// motions (calibration/synthetic_motion.hpp: the main body turning about all
// axes, the joint swinging, random axes and mount; sensors 5–25 cm from a
// moving centre for the accelerometer cases), 100 Hz, TRIALS per point:
//
//   noise      gyroscopes σ = 0.01, 0.03, 0.1, 0.3 rad/s, N = 1000: the
//              constraint fit, the likelihood fit, and the bound at the truth
//   samples    σ = 0.1 rad/s, N = 200, 500, 1000, 3000: the same
//   acc        gyroscopes 0.01 rad/s, accelerometers 0.05 m/s², N = 1000, on
//              random and on knee-like motions (wobble 0.05 rad): gyroscopes
//              alone against gyroscopes + accelerometers
//   bias       gyroscope biases N(0, 0.05²) rad/s per axis, σ = 0.01, N = 1000:
//              the constraint fit without and with --fit-gyro-bias
//   wobble     each sensor wobbling at 10–20 Hz by 0.3, 1, 3 rad/s
//              (RecordingNoise::wobble_rate), σ = 0.05, N = 1000: the
//              constraint fit without and with --low-pass 5
//
// One TSV row per trial: case, method, parameter, trial, status (ok,
// unconverged — answered with converged = false — or refused), the axis errors and σ [deg] of both axes, the bound's σ [deg]
// (constraint and likelihood rows of the same trial share it; 0 where not
// computed), the fit's wall time [s].
//
// usage: study_hinge_estimators OUT.tsv [TRIALS]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>
#include <string>

#include "calibration/hinge_fit.hpp"
#include "calibration/hinge_likelihood.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/unit_axis.hpp"

namespace {

using namespace lieflow;
using namespace lieflow::calibration;
using Clock = std::chrono::steady_clock;

constexpr double kRateHz = 100.0;


class Writer {
 public:
  explicit Writer(const std::string& path) : out_(path) {
    out_ << "case\tmethod\tparameter\ttrial\tstatus\terror_main\terror_secondary\tsigma_main\tsigma_secondary\t"
            "bound_main\tbound_secondary\tseconds\n";
  }
  bool good() const { return out_.good(); }

  /// Fits `fit` and writes its row (errors against m's axes).
  void row(const std::string& c, const std::string& method, double parameter, int trial, const HingeMotion& m,
           const HingeBound& bound, const std::function<HingeFit()>& fit) {
    const auto start = Clock::now();
    out_ << c << '\t' << method << '\t' << parameter << '\t' << trial << '\t';
    try {
      const HingeFit f = fit();
      const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
      out_ << (f.summary.converged ? "ok" : "unconverged") << '\t' << angleBetweenLines(f.axis_main, m.axis_main) * kRadToDeg << '\t'
           << angleBetweenLines(f.axis_secondary, m.axisSecondary()) * kRadToDeg << '\t' << f.sigma_main_deg << '\t'
           << f.sigma_secondary_deg << '\t' << bound.sigma_main_deg << '\t' << bound.sigma_secondary_deg << '\t'
           << seconds << '\n';
    } catch (const NotIdentifiable&) {
      const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
      out_ << "refused\t0\t0\t0\t0\t" << bound.sigma_main_deg << '\t' << bound.sigma_secondary_deg << '\t' << seconds
           << '\n';
    }
  }

 private:
  std::ofstream out_;
};

RecordingNoise gyroscopes(double sigma) {
  RecordingNoise n;
  n.rate_sigma = sigma;
  n.orientations = false;
  return n;
}

/// Constraint and likelihood fits of one recording, with the bound.
void estimators(Writer& w, const std::string& c, double parameter, int trial, std::mt19937& gen, double sigma,
                int samples) {
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples s = recordMotion(m, samples, kRateHz, gyroscopes(sigma), gen);
  const HingeBound bound = hingeCramerRao(hingeTruth(m, samples, kRateHz), sigma);
  w.row(c, "constraint", parameter, trial, m, bound, [&] { return fitHinge(s); });
  AxisFitOptions o;
  o.estimator = HingeEstimator::kLikelihood;
  w.row(c, "likelihood", parameter, trial, m, bound, [&] { return fitHinge(s, o); });
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: study_hinge_estimators OUT.tsv [TRIALS]\n";
    return 2;
  }
  const int trials = argc > 2 ? std::atoi(argv[2]) : 50;
  if (trials < 1) {
    std::cerr << "study_hinge_estimators: TRIALS must be a positive integer\n";
    return 2;
  }
  Writer w(argv[1]);
  if (!w.good()) {
    std::cerr << "study_hinge_estimators: cannot write " << argv[1] << '\n';
    return 2;
  }
  const HingeBound none;
  unsigned seed = 1;
  for (double sigma : {0.01, 0.03, 0.1, 0.3}) {
    std::mt19937 gen(seed++);
    for (int t = 0; t < trials; ++t) estimators(w, "noise", sigma, t, gen, sigma, 1000);
  }
  for (int samples : {200, 500, 1000, 3000}) {
    std::mt19937 gen(seed++);
    for (int t = 0; t < trials; ++t) estimators(w, "samples", samples, t, gen, 0.1, samples);
  }
  for (int knee = 0; knee < 2; ++knee) {
    std::mt19937 gen(seed++);
    for (int t = 0; t < trials; ++t) {
      HingeMotion m = knee ? kneeLikeHingeMotion(gen, 0.05) : randomHingeMotion(gen);
      if (!knee) m.sensors = randomSensorGeometry(gen);
      RecordingNoise n = gyroscopes(0.01);
      n.accelerometers = true;
      n.acc_sigma = 0.05;
      const JointSamples s = recordMotion(m, 1000, kRateHz, n, gen);
      AxisFitOptions gyro, acc;
      gyro.use = DataUse::kAngularVelocities;
      acc.use = DataUse::kGyroscopesAccelerometers;
      w.row(knee ? "acc_knee" : "acc_random", "gyroscopes", 0.01, t, m, none, [&] { return fitHinge(s, gyro); });
      w.row(knee ? "acc_knee" : "acc_random", "gyroscopes+accelerometers", 0.01, t, m, none,
            [&] { return fitHinge(s, acc); });
    }
  }
  {
    std::mt19937 gen(seed++);
    std::normal_distribution<double> normal;
    for (int t = 0; t < trials; ++t) {
      const HingeMotion m = randomHingeMotion(gen);
      RecordingNoise n = gyroscopes(0.01);
      n.gyro_bias_main = 0.05 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
      n.gyro_bias_secondary = 0.05 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
      const JointSamples s = recordMotion(m, 1000, kRateHz, n, gen);
      AxisFitOptions fitted;
      fitted.fit_gyro_bias = true;
      w.row("bias", "constraint", 0.05, t, m, none, [&] { return fitHinge(s); });
      w.row("bias", "constraint+bias", 0.05, t, m, none, [&] { return fitHinge(s, fitted); });
    }
  }
  for (double amplitude : {0.3, 1.0, 3.0}) {
    std::mt19937 gen(seed++);
    for (int t = 0; t < trials; ++t) {
      const HingeMotion m = randomHingeMotion(gen);
      RecordingNoise n = gyroscopes(0.05);
      n.wobble_rate = amplitude;
      const JointSamples s = recordMotion(m, 1000, kRateHz, n, gen);
      AxisFitOptions filtered;
      filtered.low_pass_hz = 5.0;
      w.row("wobble", "constraint", amplitude, t, m, none, [&] { return fitHinge(s); });
      w.row("wobble", "constraint, --low-pass 5", amplitude, t, m, none, [&] { return fitHinge(s, filtered); });
    }
  }
  return w.good() ? 0 : 1;
}
