// The time of one whole joint-axis fit (closed-form starts, Ceres refinement,
// identifiability analysis, covariance, sign resolution) on synthetic
// recordings of 1000 samples at 100 Hz (calibration/synthetic_motion.hpp), one
// thread. After the Google Benchmark table (one fixed recording per case),
// prints its median CPU times against the target (a hinge fit of 1000
// gyroscope samples in ≤ 10 ms), then a sweep over kSweepMotions random motions
// per case: CPU time per fit (median, 95th percentile, max), LM iterations,
// axis errors against the truth (median, 90th percentile, max, share within
// the accuracy target) and the honesty of σ (share of errors within
// 3σ, mean (error/σ)², which is 1 for an honest RMS σ). Then the same for
// short gyroscope recordings of the hinge (50, 100 and 200 samples at 100 Hz:
// 0.5 to 2 s), where the fit may refuse ("not identifiable") and what it
// answers must hold its σ.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bench/benchmark_support.hpp"
#include "calibration/hinge_fit.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/unit_axis.hpp"
#include "calibration/universal_fit.hpp"

namespace {

using namespace lieflow::calibration;

constexpr int kSamples = 1000;
constexpr double kRateHz = 100.0;
constexpr double kTargetHingeMs = 10.0;
constexpr int kSweepMotions = 100;

/// What one run of a fit gave (the same on every iteration: fixed data).
struct FitFigures {
  int iterations = 0;
  double error1_deg = 0.0, error2_deg = 0.0, sigma1_deg = 0.0, sigma2_deg = 0.0;
};
std::map<std::string, FitFigures>& figures() {
  static std::map<std::string, FitFigures> f;
  return f;
}

struct Case {
  std::string name;
  bool universal;
  RecordingNoise noise;
  double target_deg;  ///< the issue's accuracy target for this case (0: none stated)
};

std::vector<Case> cases() {
  RecordingNoise gyro_low{0.01, 0.0, false, true}, gyro_high{0.1, 0.0, false, true};
  RecordingNoise mocap{0.0, 0.5 / kRadToDeg, true, false}, both{0.01, 0.5 / kRadToDeg, true, true};
  return {{"hinge/gyroscopes/sigma=0.01", false, gyro_low, 0.1},
          {"hinge/gyroscopes/sigma=0.1", false, gyro_high, 0.5},
          {"hinge/orientations/0.5deg", false, mocap, 0.0},
          {"hinge/both", false, both, 0.0},
          {"universal/orientations/0.5deg", true, mocap, 0.0},
          {"universal/both", true, both, 0.2}};
}

/// Fits one recording of a fresh random motion of case c: errors, σ, iterations.
FitFigures fitOnce(const Case& c, std::mt19937& gen, double* cpu_ms, int sample_count = kSamples) {
  FitFigures f;
  std::clock_t start;
  if (!c.universal) {
    const HingeMotion motion = randomHingeMotion(gen);
    const JointSamples samples = recordMotion(motion, sample_count, kRateHz, c.noise, gen);
    start = std::clock();
    const HingeFit fit = fitHinge(samples);
    *cpu_ms = 1e3 * static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    f = {fit.summary.iterations, angleBetweenLines(fit.axis_main, motion.axis_main) * kRadToDeg,
         angleBetweenLines(fit.axis_secondary, motion.axisSecondary()) * kRadToDeg, fit.sigma_main_deg,
         fit.sigma_secondary_deg};
  } else {
    const UniversalMotion motion = randomUniversalMotion(gen);
    const JointSamples samples = recordMotion(motion, kSamples, kRateHz, c.noise, gen);
    start = std::clock();
    const UniversalFit fit = fitUniversal(samples);
    *cpu_ms = 1e3 * static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    f = {fit.summary.iterations, angleBetweenLines(fit.axis1_main, motion.axis1_main) * kRadToDeg,
         angleBetweenLines(fit.axis2_secondary, motion.axis2_secondary) * kRadToDeg, fit.sigma1_deg, fit.sigma2_deg};
  }
  return f;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * (v.size() - 1) + 0.5)];
}

void printSweep() {
  std::printf("\nsweep: %d random motions per case (1000 samples, 100 Hz); errors and sigma in degrees, both axes "
              "pooled\n",
              kSweepMotions);
  std::printf("%-30s %7s %7s %7s %5s %5s %8s %8s %8s %7s %7s %9s %9s %7s\n", "case", "cpu ms", "p95", "max", "iter",
              "max", "err med", "err p90", "err max", "target", "within", "<=3 sigma", "(e/s)^2", "refused");
  for (const Case& c : cases()) {
    std::mt19937 gen(7);
    std::vector<double> ms, errors, iterations;
    int within = 0, covered = 0, refused = 0;
    double ratio_sq = 0.0;
    for (int i = 0; i < kSweepMotions; ++i) {
      double cpu = 0.0;
      FitFigures f;
      try {
        f = fitOnce(c, gen, &cpu);
      } catch (const NotIdentifiable&) {
        ++refused;  // a motion too weak in some direction for this noise: refused, not answered
        continue;
      }
      ms.push_back(cpu);
      iterations.push_back(f.iterations);
      for (const auto& es : {std::make_pair(f.error1_deg, f.sigma1_deg), std::make_pair(f.error2_deg, f.sigma2_deg)}) {
        errors.push_back(es.first);
        within += es.first <= c.target_deg;
        covered += es.first <= 3.0 * es.second;
        ratio_sq += es.first * es.first / (es.second * es.second);
      }
    }
    const double n = static_cast<double>(errors.size());
    char target[16] = "-", share[16] = "-";
    if (c.target_deg > 0) {
      std::snprintf(target, sizeof target, "%.2f", c.target_deg);
      std::snprintf(share, sizeof share, "%.1f%%", 100.0 * within / n);
    }
    std::printf("%-30s %7.2f %7.2f %7.2f %5.0f %5.0f %8.3f %8.3f %8.3f %7s %7s %8.1f%% %9.2f %7d\n", c.name.c_str(),
                quantile(ms, 0.5), quantile(ms, 0.95), quantile(ms, 1.0), quantile(iterations, 0.5),
                quantile(iterations, 1.0), quantile(errors, 0.5), quantile(errors, 0.9), quantile(errors, 1.0), target,
                share, 100.0 * covered / n, ratio_sq / n, refused);
  }
}

/// Short gyroscope recordings of the hinge: refusals, and the honesty of what is answered.
void printShortSweep() {
  std::printf("\nshort recordings: hinge, gyroscopes, sigma = 0.01 rad/s, %d random motions per length (100 Hz); "
              "errors and sigma in degrees, both axes pooled\n",
              kSweepMotions);
  std::printf("%-10s %8s %8s %7s %7s %8s %8s %8s %9s %9s\n", "samples", "refused", "answered", "cpu ms", "max",
              "err med", "err p90", "err max", "<=3 sigma", "(e/s)^2");
  const Case c{"hinge/gyroscopes/short", false, RecordingNoise{0.01, 0.0, false, true}, 0.0};
  for (int n : {50, 100, 200}) {
    std::mt19937 gen(11);
    std::vector<double> ms, errors;
    int refused = 0, covered = 0;
    double ratio_sq = 0.0;
    for (int i = 0; i < kSweepMotions; ++i) {
      double cpu = 0.0;
      FitFigures f;
      try {
        f = fitOnce(c, gen, &cpu, n);
      } catch (const NotIdentifiable&) {
        ++refused;
        continue;
      }
      ms.push_back(cpu);
      for (const auto& es : {std::make_pair(f.error1_deg, f.sigma1_deg), std::make_pair(f.error2_deg, f.sigma2_deg)}) {
        errors.push_back(es.first);
        covered += es.first <= 3.0 * es.second;
        ratio_sq += es.first * es.first / (es.second * es.second);
      }
    }
    if (errors.empty()) {
      std::printf("%-10d %8d %8d\n", n, refused, 0);
      continue;
    }
    const double pooled = static_cast<double>(errors.size());
    std::printf("%-10d %8d %8zu %7.2f %7.2f %8.3f %8.3f %8.3f %8.1f%% %9.2f\n", n, refused, ms.size(),
                quantile(ms, 0.5), quantile(ms, 1.0), quantile(errors, 0.5), quantile(errors, 0.9),
                quantile(errors, 1.0), 100.0 * covered / pooled, ratio_sq / pooled);
  }
}

void registerCase(const Case& c) {
  benchmark::RegisterBenchmark(c.name.c_str(), [c](benchmark::State& st) {
    std::mt19937 gen(2024);
    FitFigures f;
    if (!c.universal) {
      const HingeMotion motion = randomHingeMotion(gen);
      const JointSamples samples = recordMotion(motion, kSamples, kRateHz, c.noise, gen);
      HingeFit fit;
      for (auto _ : st) {
        fit = fitHinge(samples);
        benchmark::DoNotOptimize(fit.axis_main.data());
      }
      f = {fit.summary.iterations, angleBetweenLines(fit.axis_main, motion.axis_main) * kRadToDeg,
           angleBetweenLines(fit.axis_secondary, motion.axisSecondary()) * kRadToDeg, fit.sigma_main_deg,
           fit.sigma_secondary_deg};
    } else {
      const UniversalMotion motion = randomUniversalMotion(gen);
      const JointSamples samples = recordMotion(motion, kSamples, kRateHz, c.noise, gen);
      UniversalFit fit;
      for (auto _ : st) {
        fit = fitUniversal(samples);
        benchmark::DoNotOptimize(fit.axis1_main.data());
      }
      f = {fit.summary.iterations, angleBetweenLines(fit.axis1_main, motion.axis1_main) * kRadToDeg,
           angleBetweenLines(fit.axis2_secondary, motion.axis2_secondary) * kRadToDeg, fit.sigma1_deg,
           fit.sigma2_deg};
    }
    st.counters["iterations"] = f.iterations;
    st.counters["err1_deg"] = f.error1_deg;
    st.counters["err2_deg"] = f.error2_deg;
    figures()[c.name] = f;
  })->Unit(benchmark::kMillisecond);
}

void printSummary(const lieflow::bench::MedianReporter& reporter) {
  std::printf("\n%-32s %10s %10s %12s %12s %12s %12s\n", "fit (1000 samples, 100 Hz)", "median CPU ms", "LM iter",
              "err1 deg", "sigma1 deg", "err2 deg", "sigma2 deg");
  for (const Case& c : cases()) {
    const double ms = reporter.medianNs(c.name) * 1e-6;
    if (ms < 0) continue;  // filtered out
    const FitFigures& f = figures()[c.name];
    std::printf("%-32s %10.2f %10d %12.4f %12.4f %12.4f %12.4f\n", c.name.c_str(), ms, f.iterations, f.error1_deg,
                f.sigma1_deg, f.error2_deg, f.sigma2_deg);
  }
  for (const char* name : {"hinge/gyroscopes/sigma=0.01", "hinge/gyroscopes/sigma=0.1"}) {
    const double ms = reporter.medianNs(name) * 1e-6;
    if (ms < 0) continue;
    std::printf("target %s: %.2f ms <= %.0f ms: %s\n", name, ms, kTargetHingeMs,
                ms <= kTargetHingeMs ? "PASS" : "MISS");
  }
}

}  // namespace

/// Where a default hinge fit of gyroscopes spends its time, on the fixed
/// recordings of the Google Benchmark cases (median CPU ms of 21 fits each):
/// the constraint estimator alone, the likelihood fit from it, and the
/// model check's four quarter fits.
void printHingeBreakdown() {
  std::printf("\n%-30s %12s %12s %12s\n", "hinge, 1000 gyroscope samples", "constraint", "+ likelihood",
              "+ quarters");
  for (const Case& c : cases()) {
    if (c.universal || c.noise.orientations) continue;
    std::mt19937 gen(2024);
    const HingeMotion motion = randomHingeMotion(gen);
    const JointSamples samples = recordMotion(motion, kSamples, kRateHz, c.noise, gen);
    AxisFitOptions constraint, whole, defaults;
    constraint.estimator = HingeEstimator::kConstraint;
    constraint.check_segments = whole.check_segments = false;
    double ms[3];
    int k = 0;
    for (const AxisFitOptions* o : {&constraint, &whole, &defaults}) {
      std::vector<double> t;
      for (int i = 0; i < 21; ++i) {
        const std::clock_t start = std::clock();
        const HingeFit fit = fitHinge(samples, *o);
        t.push_back(1e3 * static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC);
        benchmark::DoNotOptimize(fit.axis_main.data());
      }
      ms[k++] = quantile(t, 0.5);
    }
    std::printf("%-30s %12.2f %12.2f %12.2f\n", c.name.c_str(), ms[0], ms[1], ms[2]);
  }
}

int main(int argc, char** argv) {
  for (const Case& c : cases()) registerCase(c);
  return lieflow::bench::runWithMedianReporter(argc, argv, "0.2", [](const lieflow::bench::MedianReporter& r) {
    printSummary(r);
    printHingeBreakdown();
    printSweep();
    printShortSweep();
  });
}
