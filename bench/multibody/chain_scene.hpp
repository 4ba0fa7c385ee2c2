/// \file
/// The benchmark chain of bench_chain.cpp and bench_chain_mujoco.cpp, in one
/// place so that the lieflow and MuJoCo benchmarks time the same system:
/// dynamics/maximal/chain_builder.hpp's chain of N rods (hinge to hinge
/// 0.5 m, centre of mass 0.25 m from each hinge along body x, masses in
/// [0.5, 0.9] kg drawn with seed 42, the full inertia below for every rod),
/// hinge axes alternating z / y in the parent frame, the first hinge to ground
/// at the origin, gravity (0, 0, −9.81), stepped with h = 1e-3.
#pragma once

#include <string>
#include <variant>

#include "model/scene.hpp"

#include <Eigen/Core>

#include "dynamics/maximal/chain_builder.hpp"

namespace lieflow {
namespace bench {

/// Seed of the chain's random joint angles and masses.
constexpr unsigned kChainSeed = 42;
/// Step of the timed integrators [s].
constexpr double kChainStep = 1e-3;

/// Every rod's inertia about its centre of mass in body axes [kg m²] (products
/// of inertia included; principal moments ≈ 0.00195, 0.0093, 0.0107).
inline Eigen::Matrix3d chainRodInertia() {
  Eigen::Matrix3d I;
  I << 0.002, 0.0002, -0.0005, 0.0002, 0.01, 0.0007, -0.0005, 0.0007, 0.01;
  return I;
}

/// The chain of dynamics/maximal/chain_builder.hpp, axes alternating z / y,
/// with chainRodInertia() (state: the builder's random joint angles and rates).
inline multibody::MultibodyModel revoluteChain(int n, unsigned seed, multibody::MultibodyState* state) {
  return multibody::randomRevoluteChain(n, true, chainRodInertia(), seed, state);
}

/// The same chain as a scene (bodies at the builder's random configuration,
/// released at rest, as chainSteps runs it), for the joint-coordinate
/// formulation (dynamics/joint_space/articulated_scene.hpp).
inline SceneDescription revoluteChainScene(int n, unsigned seed) {
  multibody::MultibodyState s;
  const multibody::MultibodyModel model = revoluteChain(n, seed, &s);
  SceneDescription scene;
  scene.name = "bench chain-" + std::to_string(n);
  scene.source = scene.name;
  scene.gravity = model.gravity;
  for (std::size_t i = 0; i < model.bodies.size(); ++i) {
    BodyDescription b;
    b.name = "rod" + std::to_string(i);
    b.mass = model.bodies[i].mass;
    b.inertia = model.bodies[i].inertia;
    b.orientation = s.poses[i].R.quaternion();
    b.position = s.poses[i].p;
    b.has_position = true;
    scene.bodies.push_back(b);
  }
  auto name = [&](int i) { return i == multibody::kGround ? std::string("ground") : scene.bodies[i].name; };
  for (const multibody::Joint& j : model.joints) {
    const auto& rev = std::get<constraints::RevoluteJoint<double>>(j.constraint);
    JointDescription d;
    d.name = j.name;
    d.type = "revolute";
    d.main = name(j.main);
    d.secondary = name(j.secondary);
    d.anchor_main = rev.point.anchor_main;
    d.anchor_secondary = rev.point.anchor_secondary;
    d.axis_main = rev.axis_main;
    scene.joints.push_back(d);
  }
  return scene;
}

/// The same chain closed into a loop: a spherical joint holds the last rod's
/// free end (0.25 m along its body x from its centre of mass) at the point of
/// the ground where it is at t = 0. N − 3 degrees of freedom for N ≥ 4 (the
/// hinge axes alternate, so the loop is spatial); in joint coordinates the
/// ball joint closes the loop (3 rows with multipliers on the tree).
inline SceneDescription closedChainScene(int n, unsigned seed) {
  SceneDescription scene = revoluteChainScene(n, seed);
  scene.name = "bench closed chain-" + std::to_string(n);
  scene.source = scene.name;
  const BodyDescription& tip = scene.bodies.back();
  const Eigen::Vector3d end(0.25, 0.0, 0.0);
  JointDescription d;
  d.name = "tip";
  d.type = "spherical";
  d.main = "ground";
  d.secondary = tip.name;
  d.anchor_main = tip.orientation.normalized() * end + tip.position;
  d.anchor_secondary = end;
  scene.joints.push_back(d);
  return scene;
}

}  // namespace bench
}  // namespace lieflow
