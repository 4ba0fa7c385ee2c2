// The fit's check of its own model by activity (calibration/activity_segments.hpp,
// model_check.hpp checkAcrossRecording): a recording is cut at the middle
// of its rests, and each part is fitted alone beside the quarters by time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "calibration/activity_segments.hpp"
#include "calibration/hinge_fit.hpp"
#include "calibration/model_check.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/unit_axis.hpp"
#include "calibration_test_helpers.hpp"

namespace lieflow {
namespace calibration {
namespace {

constexpr double kRate = 100.0;

/// `rest` samples of two still bodies (gyroscopes reading white noise).
void appendRest(JointSamples* s, int rest, double sigma, std::mt19937& gen) {
  std::normal_distribution<double> noise(0.0, sigma);
  for (int k = 0; k < rest; ++k) {
    s->time.push_back(s->time.empty() ? 0.0 : s->time.back() + 1.0 / kRate);
    s->main.angular_velocity.emplace_back(noise(gen), noise(gen), noise(gen));
    s->secondary.angular_velocity.emplace_back(noise(gen), noise(gen), noise(gen));
  }
}

/// A hinge that moves in bouts and rests between them: the motion of `a`
/// (or, in every second bout, of `b`: the same motion with the secondary
/// sensor remounted, as a strap that slips while its wearer sits) on a
/// clock τ(t) that stops, τ' = 1 in a bout and 0 at rest, with smooth steps
/// of kRamp seconds. The state is the motion's at τ(t), its rates times τ'(t):
/// the gyroscopes of a motion that really comes to rest.
class BoutsAndRests final : public JointMotion {
 public:
  static constexpr double kRamp = 0.2;
  BoutsAndRests(const HingeMotion& a, const HingeMotion& b, double bout, double rest, int bouts)
      : a_(a), b_(b), bout_(bout), rest_(rest), bouts_(bouts) {
    // τ by the trapezoid on a fine grid (its error, below 1e-10 s, is far
    // under the gyroscopes' noise).
    const double end = duration();
    const int steps = static_cast<int>(end / kGrid) + 2;
    tau_.assign(steps + 1, 0.0);
    for (int k = 0; k < steps; ++k)
      tau_[k + 1] = tau_[k] + 0.5 * kGrid * (clockRate(k * kGrid) + clockRate((k + 1) * kGrid));
  }
  double duration() const { return bouts_ * bout_ + (bouts_ - 1) * rest_; }
  TwoBodyState at(double t) const override {
    const double r = clockRate(t);
    const int k = static_cast<int>(t / kGrid);
    const double tau = tau_[k] + (t - k * kGrid) / kGrid * (tau_[k + 1] - tau_[k]);
    // The slip happens in the middle of each rest.
    const int bout = static_cast<int>((t + 0.5 * rest_) / (bout_ + rest_));
    TwoBodyState x = (bout % 2 == 0 ? a_ : b_).at(tau);
    x.w1 *= r;
    x.w2 *= r;
    return x;
  }

 private:
  static constexpr double kGrid = 1e-4;
  static double smoothStep(double x) {
    x = std::min(1.0, std::max(0.0, x));
    return x * x * (3.0 - 2.0 * x);
  }
  /// τ'(t): 1 inside a bout, 0 at rest, smooth steps at the bouts' ends.
  double clockRate(double t) const {
    const int bout = std::min(bouts_ - 1, static_cast<int>(t / (bout_ + rest_)));
    const double start = bout * (bout_ + rest_), end = start + bout_;
    return smoothStep((t - start) / kRamp) * smoothStep((end - t) / kRamp);
  }
  const HingeMotion& a_;
  const HingeMotion& b_;
  double bout_, rest_;
  int bouts_;
  std::vector<double> tau_;
};

JointSamples gyroscopesOnly(const JointMotion& m, double duration, double sigma, std::mt19937& gen) {
  RecordingNoise noise = test::gyroscopeNoise(sigma);
  noise.orientations = false;
  JointSamples s = recordMotion(m, static_cast<int>(duration * kRate), kRate, noise, gen);
  s.source = "activities.csv";
  return s;
}

JointSamples emptyNamed() {
  JointSamples s;
  s.source = "activities.csv";
  s.main.name = "main";
  s.secondary.name = "secondary";
  return s;
}

/// Rests of 1 s or more cut in their middle; a shorter pause and rests at
/// either end do not cut; the parts hold every sample, in order.
TEST(CalibActivity, RestsCutTheRecordingInTheirMiddle) {
  std::mt19937 gen(3);
  const HingeMotion m = randomHingeMotion(gen);
  const BoutsAndRests bouts(m, m, 4.0, 2.0, 3);  // bouts at 0–4, 6–10, 12–16 s
  JointSamples s = gyroscopesOnly(bouts, bouts.duration(), 0.01, gen);
  const std::vector<SampleSpan> parts = activityParts(s);
  ASSERT_EQ(parts.size(), 3u);
  EXPECT_EQ(parts[0].begin, 0);
  EXPECT_EQ(parts[2].end, s.size());
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(parts[k].end, parts[k + 1].begin);
    EXPECT_NEAR(s.time[parts[k].end], 5.0 + 6.0 * k, 0.1);  // the rests' middles
  }
  // A pause of 0.5 s does not cut, nor do rests at either end.
  const BoutsAndRests paused(m, m, 4.0, 0.5, 3);
  JointSamples p = gyroscopesOnly(paused, paused.duration(), 0.01, gen);
  EXPECT_EQ(activityParts(p).size(), 1u);
  JointSamples ends = emptyNamed();
  appendRest(&ends, 200, 0.01, gen);
  for (int k = 0; k < s.size(); ++k) {
    ends.time.push_back(ends.time.back() + 1.0 / kRate);
    ends.main.angular_velocity.push_back(p.main.angular_velocity[std::min(k, p.size() - 1)]);
    ends.secondary.angular_velocity.push_back(p.secondary.angular_velocity[std::min(k, p.size() - 1)]);
  }
  appendRest(&ends, 200, 0.01, gen);
  EXPECT_EQ(activityParts(ends).size(), 1u);
}

/// Eight bouts alternate between two hinges (the secondary sensor remounted
/// 8° apart, as a strap that slips between activities), with 2 s rests
/// between. Each quarter by time holds both hinges (each answers a mixture
/// of its own); each part by activity holds one and finds it: the check
/// says one hinge does not describe the recording, each activity's axes
/// are reported, and σ includes the spread (half the 8°).
TEST(CalibActivity, AlternatingActivitiesAreToldApart) {
  std::mt19937 gen(11);
  const HingeMotion a = randomHingeMotion(gen);
  HingeMotion b = a;
  b.mount = a.mount * SO3d::exp(8.0 * M_PI / 180.0 * orthogonalUnit(a.axisSecondary()));
  const BoutsAndRests bouts(a, b, test::kSanitized ? 3.0 : 5.0, 2.0, 8);
  const JointSamples s = gyroscopesOnly(bouts, bouts.duration(), 0.01, gen);
  ASSERT_EQ(activityParts(s).size(), 8u);
  const HingeFit f = fitHinge(s, AxisFitOptions());
  int by_time = 0, by_activity = 0;
  for (const SegmentFit& seg : f.model_check.segments) (seg.by == "time" ? by_time : by_activity) += 1;
  EXPECT_EQ(by_time, 4);
  EXPECT_EQ(by_activity, 8);
  ASSERT_TRUE(f.model_check.ran) << f.model_check.note;
  EXPECT_TRUE(f.model_check.disagree) << f.model_check.note;
  EXPECT_NE(f.model_check.note.find("by activity: the 8 parts between rests that answered alone disagree"),
            std::string::npos)
      << f.model_check.note;
  // The parts of each hinge find it: within 1° of the truth, each.
  int k = 0;
  for (const SegmentFit& seg : f.model_check.segments) {
    if (seg.by != "activity") continue;
    ASSERT_TRUE(seg.answered) << seg.why;
    const HingeMotion& truth = k++ % 2 == 0 ? a : b;
    EXPECT_LT(test::lineErrorDeg(seg.secondary, truth.axisSecondary()), 1.0);
  }
  EXPECT_NEAR(f.model_check.spread_secondary, 0.5 * 8.0, 1.0);
  EXPECT_GE(f.sigma_secondary_deg, f.model_check.spread_secondary);
  std::printf("alternating hinges 8 deg apart: spread %.2f deg, sigma %.2f deg; %s\n", f.model_check.spread_secondary,
              f.sigma_secondary_deg, f.model_check.note.c_str());
}

/// One hinge throughout, four bouts and rests: both checks agree and σ is
/// the fit's own.
TEST(CalibActivity, OneHingeAcrossActivitiesAgrees) {
  std::mt19937 gen(12);
  const HingeMotion a = randomHingeMotion(gen);
  const BoutsAndRests bouts(a, a, test::kSanitized ? 3.0 : 5.0, 2.0, 4);
  const JointSamples s = gyroscopesOnly(bouts, bouts.duration(), 0.01, gen);
  const HingeFit f = fitHinge(s, AxisFitOptions());
  ASSERT_TRUE(f.model_check.ran) << f.model_check.note;
  EXPECT_FALSE(f.model_check.disagree) << f.model_check.note;
  EXPECT_NE(f.model_check.note.find("by activity: the 4 parts between rests that answered alone agree"),
            std::string::npos)
      << f.model_check.note;
  EXPECT_LT(test::lineErrorDeg(f.axis_secondary, a.axisSecondary()), 3.0 * f.sigma_secondary_deg + 1e-3);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
