// The time of one whole spring/dashpot fit (`lieflow calibrate spring`:
// AR(2) start, multiple shooting, single shooting, covariance) on a 10 s,
// 100 Hz recording (1001 samples) of the built-in free-decay scene
// `spring-hinge` (k = 12 N m/rad, c = 0.1 N m s/rad), made by the
// maximal-coordinate multibody path with Gaussian angle noise σ = 0.01 rad,
// and of a universal-joint coordinate (both angles recorded). One thread.
// After the Google Benchmark table: the median CPU time of each case against
// the target (a spring fit of 1000 samples in ≤ 2 s), the ratio of
// single to multiple shooting measured side by side, and the fitted values.
// `spring/hinge/as-mechanism` fits the same hinge recording through the
// mechanism fit (mechanism_spring_fit.hpp: the general driver, dynamic-size
// residuals, its inverse-dynamics start), which the one-joint fit's
// fixed-size driver is measured against.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "bench/benchmark_support.hpp"
#include "calibration/mechanism_spring_fit.hpp"
#include "calibration/recording.hpp"
#include "calibration/spring_fit.hpp"
#include "calibration/synthetic_spring.hpp"
#include "calibration/spring_joint.hpp"
#include "model/scene.hpp"

namespace {

using namespace lieflow;
using namespace lieflow::calibration;

constexpr double kTargetSeconds = 2.0;
constexpr double kNoise = 0.01;

struct Case {
  std::string name;
  bool universal;
  SpringFitOptions options;
  double k_true, c_true;
};

std::vector<Case> cases() {
  SpringFitOptions multiple, single, rest, far, universal;
  single.shooting = Shooting::kSingle;
  rest.fit_rest_angle = true;
  far.stiffness_start = 36.0;  // 3 × the truth
  far.damping_start = 0.3;
  universal.coordinate = 1;
  return {{"spring/hinge/multiple", false, multiple, 12.0, 0.1},
          {"spring/hinge/single", false, single, 12.0, 0.1},
          {"spring/hinge/fit-rest-angle", false, rest, 12.0, 0.1},
          {"spring/hinge/start-3x", false, far, 12.0, 0.1},
          {"spring/universal/coordinate-2", true, universal, 10.0, 0.08}};
}

std::map<std::string, SpringFit>& fits() {
  static std::map<std::string, SpringFit> f;
  return f;
}

void registerCase(const Case& c, const SpringJoint* hinge, const SpringData* hinge_data,
                  const SpringJoint* universal, const SpringData* universal_data) {
  benchmark::RegisterBenchmark(c.name.c_str(), [=](benchmark::State& st) {
    const SpringJoint& joint = c.universal ? *universal : *hinge;
    const SpringData& data = c.universal ? *universal_data : *hinge_data;
    SpringFit fit;
    for (auto _ : st) {
      fit = fitSpring(joint, data, c.options);
      // The const overload (an input operand): the non-const one, "+m,r",
      // was seen to clobber the double with GCC 12 and benchmark 1.7.1.
      benchmark::DoNotOptimize(static_cast<const double&>(fit.stiffness));
    }
    st.counters["iterations"] = fit.iterations;
    st.counters["samples"] = fit.samples;
    fits()[c.name] = fit;
  })->Unit(benchmark::kMillisecond);
}

constexpr const char* kAsMechanism = "spring/hinge/as-mechanism";

MechanismSpringFit& mechanismFit() {
  static MechanismSpringFit f;
  return f;
}

/// The one-joint recording as the mechanism fit reads it: the joint's angle column.
Recording asRecording(const SpringData& data) {
  Recording r;
  r.source = data.source;
  r.time = data.time;
  r.scalars.push_back({"hinge.phi", data.angle[0]});
  return r;
}

void registerMechanismCase(const SceneDescription* scene, const Recording* recording) {
  benchmark::RegisterBenchmark(kAsMechanism, [=](benchmark::State& st) {
    MechanismSpringFit fit;
    for (auto _ : st) {
      fit = fitMechanismSprings(*scene, *recording, MechanismSpringOptions());
      benchmark::DoNotOptimize(static_cast<const double&>(fit.coordinates[0].stiffness));
    }
    st.counters["iterations"] = fit.iterations;
    mechanismFit() = fit;
  })->Unit(benchmark::kMillisecond);
}

void printSummary(const lieflow::bench::MedianReporter& reporter) {
  std::printf("\n%-30s %9s %6s %5s %5s %12s %10s %11s %10s %9s\n", "fit (10 s, 100 Hz, 0.01 rad)", "CPU ms",
              "target", "iter", "segs", "stiffness", "k sigma", "damping", "c sigma", "k err %");
  for (const Case& c : cases()) {
    const double ms = reporter.medianNs(c.name) * 1e-6;
    if (ms < 0) continue;  // filtered out
    const SpringFit& f = fits()[c.name];
    std::printf("%-30s %9.2f %6s %5d %5d %12.6f %10.6f %11.7f %10.7f %9.3f\n", c.name.c_str(), ms,
                ms <= 1e3 * kTargetSeconds ? "PASS" : "MISS", f.iterations, f.segments, f.stiffness,
                f.stiffness_sigma, f.damping, f.damping_sigma, 100.0 * (f.stiffness / c.k_true - 1.0));
  }
  const double ms = reporter.medianNs(kAsMechanism) * 1e-6;
  if (ms >= 0 && !mechanismFit().coordinates.empty()) {
    const CoordinateSpring& c = mechanismFit().coordinates[0];
    std::printf("%-30s %9.2f %6s %5d %5d %12.6f %10.6f %11.7f %10.7f %9.3f\n", kAsMechanism, ms,
                ms <= 1e3 * kTargetSeconds ? "PASS" : "MISS", mechanismFit().iterations, mechanismFit().segments,
                c.stiffness, c.stiffness_sigma, c.damping, c.damping_sigma, 100.0 * (c.stiffness / 12.0 - 1.0));
  }
  const double m = reporter.medianNs("spring/hinge/multiple"), s = reporter.medianNs("spring/hinge/single");
  if (m > 0 && s > 0) std::printf("single / multiple shooting CPU time: %.2f\n", s / m);
  if (m > 0 && ms >= 0) std::printf("the hinge as a mechanism / the one-joint fit: %.2f\n", ms * 1e6 / m);
}

}  // namespace

int main(int argc, char** argv) {
  const SceneDescription hinge_scene = loadScene("spring-hinge");
  const SceneDescription universal_scene = parseScene(kSpringUniversalSceneJson, "spring-universal");
  const SpringJoint hinge = springJoint(hinge_scene, "hinge");
  const SpringJoint universal = springJoint(universal_scene, "cross");
  const SpringData hinge_data = withAngleNoise(simulatedJointAngles(hinge_scene, "hinge", 1, 10.0), kNoise, 17);
  const SpringData universal_data =
      withAngleNoise(simulatedJointAngles(universal_scene, "cross", 2, 10.0), kNoise, 17);
  for (const Case& c : cases()) registerCase(c, &hinge, &hinge_data, &universal, &universal_data);
  const Recording hinge_recording = asRecording(hinge_data);
  registerMechanismCase(&hinge_scene, &hinge_recording);
  return lieflow::bench::runWithMedianReporter(argc, argv, "0.2", printSummary);
}
