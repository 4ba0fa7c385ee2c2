/// `autonomous()` of the systems (radau5 evaluates a start from rest once
/// when it is true): checked against what it claims, f(t, y) the same at
/// every t, on every jointed built-in scene in both formulations and on a
/// heavy top; false exactly on the scenes with prescribed motion or applied
/// moments of time (a cautious answer: a shaft driven at a constant rate may
/// leave f unchanged, the driven arm's sine does not).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include <Eigen/Core>

#include "dynamics/joint_space/articulated_scene.hpp"
#include "dynamics/maximal/multibody_scene.hpp"
#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "model/scene.hpp"

namespace lieflow {
namespace {

/// max |f(t, y) − f(0, y)| over a few times t.
template <typename System, typename State>
double changeWithTime(const System& system, const State& y) {
  Eigen::VectorXd f0, f;
  system.velocity(0.0, y, &f0);
  double change = 0.0;
  for (double t : {0.37, 1.3, 2.9}) {
    system.velocity(t, y, &f);
    change = std::max(change, (f - f0).cwiseAbs().maxCoeff());
  }
  return change;
}

TEST(Autonomous, TrueExactlyWhereTheRightHandSideIgnoresTime) {
  // The jointed scenes whose drives hold prescribed motion or moments M(t).
  const std::set<std::string> timed = {"cardan-shaft", "differential", "driven-arm",
                                       "hinge-pair",   "rack-pinion",  "universal-pair"};
  const std::set<std::string> jointed = {"cardan-shaft", "differential", "double-pendulum", "driven-arm",
                                         "gear-train",   "hinge-pair",   "pendulum",        "rack-pinion",
                                         "slider-crank", "spring-hinge", "stiff-hinge",     "universal-pair"};
  for (const std::string& name : jointed) {
    SCOPED_TRACE(name);
    const SceneDescription scene = loadScene(name);
    const bool expected = timed.count(name) == 0;
    // The claim, and f against it (the driven arm's sine moves f).
    const auto check = [&](const auto& system, const auto& y0, const char* formulation) {
      SCOPED_TRACE(formulation);
      EXPECT_EQ(system.autonomous(), expected);
      const double change = changeWithTime(system, y0);
      if (expected) {
        EXPECT_EQ(change, 0.0);
      }
      if (name == "driven-arm") {
        EXPECT_GT(change, 0.0);
      }
    };
    const auto maximal = assembleMultibody(scene);
    check(*maximal->system, maximal->y0, "maximal");
    std::string why;
    if (!articulatedCovers(scene, &why)) continue;
    const auto joint = assembleArticulated(scene);
    check(*joint->system, joint->y0, "joint");
  }
}

TEST(Autonomous, ASingleBodyWithATorqueOfTimeIsNot) {
  RigidBodyParameters<double> p;
  p.inertia = Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal();
  p.has_pivot = true;
  p.com_from_pivot = Eigen::Vector3d(0.0, 0.0, 0.5);
  p.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  RotorState<double> y;
  y.omega = Eigen::Vector3d(0.3, -1.0, 2.0);
  const RotorSystem<double> top(p);
  EXPECT_TRUE(top.autonomous());
  Eigen::Matrix<double, 6, 1> f0, f1;
  top.velocity(0.0, y, &f0);
  top.velocity(1.3, y, &f1);
  EXPECT_EQ(f0, f1);
  p.torque_body = [](double t) { return Eigen::Vector3d(std::sin(t), 0.0, 0.0); };
  const RotorSystem<double> driven(p);
  EXPECT_FALSE(driven.autonomous());
  driven.velocity(0.0, y, &f0);
  driven.velocity(1.3, y, &f1);
  EXPECT_NE(f0, f1);
}

}  // namespace
}  // namespace lieflow
