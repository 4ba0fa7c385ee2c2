/// \file
/// A chain of rods on revolute joints with a random state consistent with the
/// joints: the scene of the chain-scaling tests and benchmarks.
#pragma once

#include <random>
#include <string>

#include "dynamics/maximal/multibody_model.hpp"

namespace lieflow {
namespace multibody {

/// N rods (centre of mass 0.25 m from each hinge along body x) on revolute
/// joints, the first to ground at the origin. Hinge axes alternate z / y in
/// the parent frame when `alternate`, else all z. Joint angles are uniform
/// in [−1, 1] rad, joint rates in [−3, 3] rad/s, masses in [0.5, 0.9] kg;
/// positions and velocities follow from the joints, so the state satisfies
/// the constraints at position and velocity level.
inline MultibodyModel randomRevoluteChain(int n, bool alternate, const Eigen::Matrix3d& inertia,
                                          unsigned seed, MultibodyState* state) {
  using Eigen::Vector3d;
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Vector3d half(0.25, 0, 0);
  MultibodyModel model;
  state->poses.clear();
  state->velocities.clear();
  SO3d Rprev = SO3d::identity();
  Vector3d wprev = Vector3d::Zero(), tip = Vector3d::Zero(), tip_v = Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Vector3d a = alternate && (i % 2) ? Vector3d(0, 1, 0) : Vector3d(0, 0, 1);
    const SO3d R = Rprev * SO3d::exp(u(gen) * a);
    const Vector3d w = wprev + R.matrix() * (3 * u(gen) * a);  // world
    const Vector3d p = tip + R.matrix() * half;
    const Vector3d v = tip_v + w.cross(R.matrix() * half);
    model.addBody(RigidBody{"rod" + std::to_string(i), 0.5 + 0.2 * (u(gen) + 1.0), inertia, false});
    const constraints::BodyPose<double> pose{R, p};
    const constraints::BodyPose<double> parent =
        i == 0 ? constraints::groundPose<double>() : state->poses.back();
    model.addJoint(Joint{"hinge" + std::to_string(i), i - 1, i,
                         constraints::assembleRevoluteJoint<double>(
                             parent, pose, i == 0 ? Vector3d::Zero() : half, -half, a, a)});
    state->poses.push_back(pose);
    state->velocities.push_back(constraints::BodyVelocity<double>{v, R.matrix().transpose() * w});
    Rprev = R;
    wprev = w;
    tip = p + R.matrix() * half;
    tip_v = v + w.cross(R.matrix() * half);
  }
  return model;
}

}  // namespace multibody
}  // namespace lieflow
