// A scene's fastest time scale (scene_time_scale.hpp).
#include "model/scene_time_scale.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "liegroup/invalid_input.hpp"

namespace lieflow {

double characteristicFrequency(const SceneDescription& scene) {
  double omega = 0.0;
  for (const BodyDescription& b : scene.bodies) {
    omega = std::max(omega, b.angular_velocity.norm());
    if (b.spring_stiffness > 0.0) {
      const double i_min = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(b.inertia).eigenvalues().minCoeff();
      omega = std::max(omega, std::sqrt(b.spring_stiffness / i_min));
    }
  }
  // Joint springs: √(k / I_a), I_a the secondary body's moment of inertia
  // about the joint axis through the anchor at t = 0 (parallel axes; the main
  // body held), the frequency of that joint alone; a prismatic spring
  // √(k / m) with the secondary body's mass.
  for (const JointDescription& j : scene.joints) {
    if (j.type == "prismatic" && j.coordinates[0].stiffness > 0.0) {
      const int bi = scene.bodyIndex(j.secondary);
      if (bi >= 0) omega = std::max(omega, std::sqrt(j.coordinates[0].stiffness / scene.bodies[bi].mass));
      continue;
    }
    if (j.type != "revolute" && j.type != "universal" && j.type != "gimbal") continue;
    const int bi = scene.bodyIndex(j.secondary);
    const int ai = scene.bodyIndex(j.main);
    if (bi < 0) continue;
    const BodyDescription& b = scene.bodies[bi];
    const Eigen::Matrix3d Rb = b.orientation.toRotationMatrix();
    const Eigen::Matrix3d Ra = ai < 0 ? Eigen::Matrix3d::Identity()
                                      : Eigen::Matrix3d(scene.bodies[ai].orientation.toRotationMatrix());
    // The hinge axes at t = 0 (a gimbal's given in the main frame at zero
    // angles: close enough for a time scale).
    const std::array<Eigen::Vector3d, 3> axes = {
        Eigen::Vector3d((Ra * j.axis_main).normalized()),
        Eigen::Vector3d(j.type == "gimbal" ? (Ra * j.axis2_main).normalized() : (Rb * j.axis_secondary).normalized()),
        Eigen::Vector3d((Ra * j.axis3_main).normalized())};
    const int coordinates = j.type == "revolute" ? 1 : j.type == "universal" ? 2 : 3;
    for (int i = 0; i < coordinates; ++i) {
      const double k = j.coordinates[i].stiffness;
      if (!(k > 0.0)) continue;
      const Eigen::Vector3d& a = axes[i];
      const Eigen::Vector3d d = Rb * j.anchor_secondary;  // CoM → anchor, world
      const double lever2 = b.rotation_only ? 0.0 : (d - d.dot(a) * a).squaredNorm();
      const double I = a.dot(Rb * b.inertia * Rb.transpose() * a) + b.mass * lever2;
      omega = std::max(omega, std::sqrt(k / I));
    }
  }
  if (!(omega > 0.0))
    throw InvalidInput(scene.source, "no time scale for a stability study (no spin, no spring)");
  return omega;
}

}  // namespace lieflow
