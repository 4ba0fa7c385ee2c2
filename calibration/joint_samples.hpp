/// \file
/// The samples of one joint's two bodies that a calibration fits: the times
/// and, per body, the orientations R (body → world) and/or the body-frame
/// angular velocities ω (what a gyroscope on the body measures). Either list
/// of a body may be empty (that column group was not recorded); when present
/// it has one entry per time.
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "liegroup/so3.hpp"

namespace lieflow {
namespace calibration {

/// One body's recorded motion.
struct BodySamples {
  std::string name;
  std::vector<SO3d> orientation;                    ///< R(t_k); empty when not recorded
  std::vector<Eigen::Vector3d> angular_velocity;    ///< ω(t_k), body frame; empty when not recorded
  /// The accelerometer's specific force f(t_k) = Rᵀ(a_s − g) [m/s²], body
  /// frame, at the sensor point (B.ax, B.ay, B.az); empty when not recorded.
  std::vector<Eigen::Vector3d> specific_force;

  bool hasOrientation() const { return !orientation.empty(); }
  bool hasAngularVelocity() const { return !angular_velocity.empty(); }
  bool hasSpecificForce() const { return !specific_force.empty(); }
};

/// The two bodies of a joint: `main` (body 1, the frame of `axis_main`) and
/// `secondary` (body 2), sampled at the same times.
struct JointSamples {
  std::string source;  ///< where the samples came from (file name), for messages
  std::vector<double> time;
  BodySamples main;
  BodySamples secondary;

  int size() const { return static_cast<int>(time.size()); }
  /// The mean sampling interval (t_last − t_first)/(n − 1); needs n ≥ 2.
  double meanStep() const { return (time.back() - time.front()) / (size() - 1); }
  bool hasOrientations() const { return main.hasOrientation() && secondary.hasOrientation(); }
  bool hasAngularVelocities() const {
    return main.hasAngularVelocity() && secondary.hasAngularVelocity();
  }
};

/// Samples [begin, end) of `samples`, every recorded column sliced alike
/// (a column not recorded stays empty).
inline JointSamples samplesBetween(const JointSamples& samples, int begin, int end) {
  const auto cut = [begin, end](const auto& v) {
    using V = std::decay_t<decltype(v)>;
    return v.empty() ? V() : V(v.begin() + begin, v.begin() + end);
  };
  JointSamples out;
  out.source = samples.source;
  out.time = cut(samples.time);
  for (int b = 0; b < 2; ++b) {
    const BodySamples& from = b == 0 ? samples.main : samples.secondary;
    BodySamples& to = b == 0 ? out.main : out.secondary;
    to.name = from.name;
    to.orientation = cut(from.orientation);
    to.angular_velocity = cut(from.angular_velocity);
    to.specific_force = cut(from.specific_force);
  }
  return out;
}

}  // namespace calibration
}  // namespace lieflow
