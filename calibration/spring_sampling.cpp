#include "calibration/spring_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "joints/resource_limits.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

std::string num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

/// "coordinate 1 of joint 'hinge'".
std::string coordinateName(const GroundedJointScene& joint, int i) {
  return "coordinate " + std::to_string(i + 1) + " of joint '" + joint.joint_name + "'";
}

}  // namespace

double fastestRate(double inertia, double effective_stiffness, double damping) {
  return std::max(std::sqrt(std::abs(effective_stiffness) / inertia), std::abs(damping) / inertia);
}

SpringSampling checkSpringSampling(const GroundedJointScene& joint, const SpringData& data, int coordinate,
                                   const SpringStartValues& start, const Eigen::Vector2d& mean_angle,
                                   int substeps_option, long max_substeps) {
  SpringSampling out;
  const int n = data.size();
  const std::string time_field = data.source + ": t";
  for (int j = 0; j + 1 < n; ++j) out.max_interval = std::max(out.max_interval, data.time[j + 1] - data.time[j]);
  if (!std::isfinite(out.max_interval) || !std::isfinite(data.time.back() - data.time.front()))
    throw InvalidInput(time_field, "the recording spans " + num(data.time.front()) + " … " + num(data.time.back()) +
                                       " s, beyond the range of numbers the fit can integrate over");
  const double D = out.max_interval;
  const double rate_limit = kNyquistRateTimesInterval / D;
  const std::string cannot_show = ", faster than samples " + num(D) + " s apart can show (Nyquist: at most " +
                                  num(rate_limit) + " rad/s)";
  const std::string is_t_seconds = "; is t in seconds?";

  const int ic = coordinate;
  const double I = joint.inertiaAbout(ic, mean_angle);
  const double k_gravity = joint.gravityStiffness(ic, mean_angle);
  const double k = start.value[0], c = start.value[1];

  // What the recording itself gave (a start read from its oscillation).
  if (start.recorded_period > 0.0 &&
      (!std::isfinite(start.recorded_frequency) ||
       (start.origin[0] == StartOrigin::kRecording && !std::isfinite(k)) ||
       (start.origin[1] == StartOrigin::kRecording && !std::isfinite(c))))
    throw InvalidInput(time_field, "the recorded angle oscillates with a period of " + num(start.recorded_period) +
                                       " s (from its zero crossings): with the scene's inertia " + num(I) +
                                       " kg m^2 that is a stiffness I ω² beyond the range of double, which the fit "
                                       "cannot integrate" + is_t_seconds);
  if (start.recorded_frequency * D > kNyquistRateTimesInterval)
    throw InvalidInput(time_field, "the recorded angle's oscillation (period " + num(start.recorded_period) +
                                       " s from its zero crossings) is at " + num(start.recorded_frequency) +
                                       " rad/s" + cannot_show + is_t_seconds);

  // The scene alone: gravity on the fitted coordinate, everything on the other.
  for (int i = 0; i < joint.coordinates; ++i) {
    const double Ii = joint.inertiaAbout(i, mean_angle);
    const double kg = joint.gravityStiffness(i, mean_angle);
    const bool fitted = i == ic;
    const double rate = fitted ? fastestRate(Ii, kg, 0.0)
                               : fastestRate(Ii, joint.drives[i].stiffness + kg, joint.drives[i].damping);
    if (rate * D > kNyquistRateTimesInterval)
      throw InvalidInput(time_field, "the largest sample interval " + num(D) + " s is longer than half a period (" +
                                         num(3.141592653589793 / rate) + " s) of the motion that the scene's " +
                                         (fitted ? "gravity gives " : "spring, dashpot and gravity give ") +
                                         coordinateName(joint, i) + " (" + num(rate) +
                                         " rad/s): the recording cannot show it" + is_t_seconds);
    out.fastest_rate = std::max(out.fastest_rate, rate);
  }

  // The start of the fitted coordinate, blamed on where it came from.
  auto blame = [&](int which, const std::string& what, const std::string& largest) {
    switch (start.origin[which]) {
      case StartOrigin::kGiven:
        return InvalidInput(which == 0 ? "--stiffness-start" : "--damping-start", what + cannot_show + "; " + largest);
      case StartOrigin::kRecording:
        return InvalidInput(time_field, "the start read from the recorded angle (period " +
                                            num(start.recorded_period) + " s): " + what + cannot_show + is_t_seconds);
      case StartOrigin::kScene: break;
    }
    return InvalidInput(time_field, "the start taken from the scene's " +
                                        std::string(which == 0 ? "spring" : "dashpot") +
                                        " (the recording gave none): " + what + cannot_show + is_t_seconds +
                                        " Otherwise give " + (which == 0 ? "--stiffness-start" : "--damping-start"));
  };
  const double rate_k = std::sqrt(std::abs(k + k_gravity) / I);
  if (!(rate_k * D <= kNyquistRateTimesInterval))
    throw blame(0,
                num(k) + " N m/rad would make " + coordinateName(joint, ic) + " oscillate at " + num(rate_k) +
                    " rad/s (with the scene's inertia " + num(I) + " kg m^2 and gravity stiffness " + num(k_gravity) +
                    " N m/rad)",
                "the recording allows a stiffness of at most " + num(I * rate_limit * rate_limit - k_gravity) +
                    " N m/rad");
  const double rate_c = c / I;
  if (!(rate_c * D <= kNyquistRateTimesInterval))
    throw blame(1,
                num(c) + " N m s/rad would damp " + coordinateName(joint, ic) + " at c/I = " + num(rate_c) +
                    " 1/s (a time constant of " + num(1.0 / rate_c) + " s with the scene's inertia " + num(I) +
                    " kg m^2)",
                "the recording allows a damping of at most " + num(I * rate_limit) + " N m s/rad");
  out.fastest_rate = std::max({out.fastest_rate, rate_k, rate_c, start.recorded_frequency});

  // Substeps per interval, counted in double (they are bounded only by the limit).
  const double intervals = n - 1;
  const double per_interval =
      substeps_option > 0 ? substeps_option
                          : std::max(1.0, std::ceil(kSubstepRateMargin * out.fastest_rate * D / kStepTimesFrequency));
  out.total_substeps = per_interval * intervals;
  if (!(out.total_substeps <= static_cast<double>(max_substeps))) {
    if (substeps_option > 0)
      throw limitExceeded("--substeps", "integration substeps (" + num(per_interval) + " per sample interval over " +
                                            num(intervals) + " intervals)",
                          out.total_substeps, static_cast<double>(max_substeps), "--max-substeps");
    throw limitExceeded(time_field,
                        "integration substeps (" + num(per_interval) + " per sample interval: the largest interval " +
                            num(D) + " s at the start's fastest rate " + num(out.fastest_rate) + " rad/s, over " +
                            num(intervals) + " intervals)",
                        out.total_substeps, static_cast<double>(max_substeps), "--max-substeps");
  }
  out.substeps = static_cast<int>(per_interval);
  return out;
}

}  // namespace calibration
}  // namespace lieflow
