/// \file
/// The one-joint spring fit's model (calibration/spring_joint.hpp: one body
/// on a revolute or universal joint to ground as the one-body tree of the
/// joint formulation's dynamics on any scalar, a grounded hinge in its closed
/// form, advanced by the fit's RKMK flow of spring_residuals.hpp), checked
/// against the maximal-coordinate multibody path of `lieflow simulate` (an
/// independent formulation: five or four constraint rows with multipliers,
/// body by body on SO(3) × ℝ³) on the same scenes, with the body on either
/// side of the joint, tilted axes, a full inertia matrix, gravity, springs,
/// dashpots and an applied moment; plus energy conservation and the scenes it
/// must refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "integrators/butcher_tableau.hpp"
#include "integrators/rkmk.hpp"
#include "calibration/spring_joint.hpp"
#include "calibration/spring_residuals.hpp"
#include "model/scene.hpp"
#include "simulation/simulation.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

std::string json(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s.precision(17);
  s << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

std::string json(const Eigen::Quaterniond& q) {
  std::ostringstream s;
  s.precision(17);
  s << "[" << q.w() << ", " << q.x() << ", " << q.y() << ", " << q.z() << "]";
  return s.str();
}

/// A scene with one body `arm` (full inertia matrix, orientation R0) on a
/// joint to ground at the world point o, anchored at s (body frame). The
/// joint's axis fields and coordinate fields are given as JSON text.
std::string armScene(const std::string& type, bool body_main, const Eigen::Quaterniond& R0,
                     const Eigen::Vector3d& o, const Eigen::Vector3d& s, const std::string& joint_fields,
                     const Eigen::Vector3d& omega0) {
  const Eigen::Vector3d position = o - R0 * s;  // the anchors coincide
  std::ostringstream j;
  j << R"({"name": "arm-test", "gravity": [0.3, -0.2, -9.81], "bodies": [{"name": "arm", "mass": 1.7,)"
    << R"( "inertia": [[0.09, 0.004, -0.006], [0.004, 0.07, 0.002], [-0.006, 0.002, 0.03]],)"
    << R"( "orientation": )" << json(R0) << R"(, "position": )" << json(position)
    << R"(, "angular_velocity": )" << json(omega0) << "}], "
    << R"("joints": [{"name": "j", "type": ")" << type << R"(", "main": ")" << (body_main ? "arm" : "ground")
    << R"(", "secondary": ")" << (body_main ? "ground" : "arm") << R"(", "anchor_main": )"
    << json(body_main ? s : o) << R"(, "anchor_secondary": )" << json(body_main ? o : s)
    << (joint_fields.empty() ? "" : ", ") << joint_fields << "}]}";
  return j.str();
}

/// Joint angles of a full run (columns J.phi or J.phi1, J.phi2), every row.
std::vector<Eigen::Vector2d> fullAngles(const SceneDescription& scene, const std::string& joint, double dt,
                                        double t_end) {
  const Simulation sim(scene);
  const std::vector<std::string> columns = sim.columns();
  auto col = [&](const std::string& name) {
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name) return static_cast<int>(i);
    return -1;
  };
  const int c1 = col(joint + ".phi") >= 0 ? col(joint + ".phi") : col(joint + ".phi1");
  const int c2 = col(joint + ".phi2");
  EXPECT_GE(c1, 0);
  std::vector<Eigen::Vector2d> out;
  SimulationOptions o;
  o.integrator = "rkmk4";
  o.dt = dt;
  o.t_end = t_end;
  const SimulationResult r = sim.run(o, [&](const std::vector<double>& row) {
    out.emplace_back(row[c1], c2 >= 0 ? row[c2] : 0.0);
  });
  EXPECT_FALSE(r.failed) << r.failure;
  return out;
}

/// The fit's model's angles with rkmk4 at the same step, every step.
template <int N>
std::vector<Eigen::Vector2d> reducedAngles(const SpringJoint& g, double dt, int steps,
                                           std::vector<double>* energy = nullptr) {
  articulated::CoordinateForces<double> forces;  // for the energy
  JointSprings<double, N> springs;
  for (int i = 0; i < N; ++i) {
    forces.stiffness.push_back(g.drives[i].stiffness);
    forces.rest_angle.push_back(g.drives[i].rest_angle);
    forces.damping.push_back(g.drives[i].damping);
    springs.stiffness[i] = forces.stiffness[i];
    springs.rest_angle[i] = forces.rest_angle[i];
    springs.damping[i] = forces.damping[i];
  }
  const articulated::ScalarDynamics<double> dynamics(g.model());
  const SpringJointFlow<double, N> system(g.model(), dynamics.groundedHinge(), springs);
  const RkmkStepper<VectorState<double, N>> stepper(ButcherTableau::rk4());
  VectorState<double, N> y;
  y.x = g.initial_angle.head<N>();
  y.v = g.initial_rate.head<N>();
  std::vector<Eigen::Vector2d> out;
  for (int k = 0; k <= steps; ++k) {
    Eigen::Vector2d phi = Eigen::Vector2d::Zero();
    phi.head<N>() = y.x;
    out.push_back(phi);
    if (energy) energy->push_back(dynamics.energy(y.x, y.v, forces));
    if (k < steps) y = stepper.step(system, k * dt, y, dt);
  }
  return out;
}

double maxDifference(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b) {
  EXPECT_EQ(a.size(), b.size());
  double d = 0.0;
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) d = std::max(d, (a[k] - b[k]).lpNorm<Eigen::Infinity>());
  return d;
}

const Eigen::Quaterniond kR0 = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()));
const Eigen::Vector3d kPivot(0.1, -0.2, 0.4);
const Eigen::Vector3d kAnchor(0.05, 0.1, 0.35);

TEST(SpringJoint, SpringHingeSceneMatchesTheMultibodyPath) {
  const SceneDescription scene = loadScene("spring-hinge");
  const SpringJoint g = springJoint(scene, "");
  EXPECT_EQ(g.joint_name, "hinge");
  EXPECT_EQ(g.body_name, "bar");
  EXPECT_DOUBLE_EQ(g.initial_angle[0], 0.8);
  // Inertia about the axis: I_yy + m d² = 0.06 + 2 · 0.09.
  EXPECT_NEAR(g.inertiaAbout(0, g.initial_angle), 0.24, 1e-14);
  // Gravity moment −m g d sin φ about +y.
  EXPECT_NEAR(g.gravityMoment(0, g.initial_angle), -2.0 * 9.81 * 0.3 * std::sin(0.8), 1e-13);
  const double dt = 1e-3;
  const auto full = fullAngles(scene, "hinge", dt, 3.0);
  EXPECT_TRUE(articulated::ScalarDynamics<double>(g.model()).closedForm());
  const auto reduced = reducedAngles<1>(g, dt, 3000);
  EXPECT_LT(maxDifference(full, reduced), 1e-10);  // measured 1.1e-11
}

struct Case {
  const char* name;
  std::string type;
  bool body_main;
  std::string fields;
};

class SpringJointCases : public ::testing::TestWithParam<int> {};

Case makeCase(int i) {
  const Eigen::Vector3d a = Eigen::Vector3d(0.2, 1.0, -0.3).normalized();
  const Eigen::Vector3d body_a = kR0.inverse() * a;  // the same axis in the body frame
  const Eigen::Vector3d e2 = a.cross(Eigen::Vector3d(0.1, 0.3, 1.0)).normalized();  // ⟂ a, world
  const std::string springs =
      R"("spring": {"stiffness": 3.0, "rest_angle": 0.2}, "damper": {"damping": 0.05}, )"
      R"("moment": {"type": "sine", "amplitude": 0.4, "frequency": 0.7})";
  const std::string springs1 = R"("spring1": {"stiffness": 2.0, "rest_angle": -0.1}, "damper1": {"damping": 0.03}, )"
                               R"("moment1": {"type": "sine", "amplitude": 0.3, "frequency": 0.5}, )"
                               R"("spring2": {"stiffness": 4.0}, "damper2": {"damping": 0.02})";
  switch (i) {
    case 0:
      return {"revolute, body secondary", "revolute", false,
              R"("axis_main": )" + json(a) + R"(, "initial_angle": 0.4, )" + springs};
    case 1:
      return {"revolute, body main", "revolute", true,
              R"("axis_main": )" + json(body_a) + R"(, "initial_angle": -0.3, )" + springs};
    case 2:
      return {"universal, body secondary", "universal", false,
              R"("axis1_main": )" + json(a) + R"(, "axis2_secondary": )" + json(kR0.inverse() * e2) +
                  R"(, "initial_angles": [0.3, -0.2], )" + springs1};
    default:
      return {"universal, body main", "universal", true,
              R"("axis1_main": )" + json(body_a) + R"(, "axis2_secondary": )" + json(e2) +
                  R"(, "initial_angles": [-0.25, 0.35], )" + springs1};
  }
}

TEST_P(SpringJointCases, MatchesTheMultibodyPath) {
  const Case c = makeCase(GetParam());
  SCOPED_TRACE(c.name);
  const SceneDescription scene =
      parseScene(armScene(c.type, c.body_main, kR0, kPivot, kAnchor, c.fields, Eigen::Vector3d(1.5, -2.0, 2.5)),
                 "arm-test.json");
  const SpringJoint g = springJoint(scene, "j");
  EXPECT_EQ(g.body_is_main, c.body_main);
  // The assembled initial rates are not all zero (the projection kept part of ω₀).
  EXPECT_GT(g.initial_rate.norm(), 0.1);
  const double dt = 1e-3;
  const auto full = fullAngles(scene, "j", dt, 2.0);
  const auto reduced = g.coordinates == 1 ? reducedAngles<1>(g, dt, 2000) : reducedAngles<2>(g, dt, 2000);
  EXPECT_LT(maxDifference(full, reduced), 1e-11);  // measured 1.9e-14 to 3.5e-13
}

INSTANTIATE_TEST_SUITE_P(BodySideAndType, SpringJointCases, ::testing::Values(0, 1, 2, 3));

TEST(SpringJoint, UniversalEnergyIsConservedToFourthOrder) {
  const Eigen::Vector3d a = Eigen::Vector3d(0.2, 1.0, -0.3).normalized();
  const Eigen::Vector3d e2 = a.cross(Eigen::Vector3d(0.1, 0.3, 1.0)).normalized();
  const std::string fields = R"("axis1_main": )" + json(a) + R"(, "axis2_secondary": )" +
                             json(kR0.inverse() * e2) +
                             R"(, "initial_angles": [0.3, -0.2], "spring1": {"stiffness": 2.0}, )"
                             R"("spring2": {"stiffness": 4.0, "rest_angle": 0.5})";
  const SceneDescription scene = parseScene(
      armScene("universal", false, kR0, kPivot, kAnchor, fields, Eigen::Vector3d(1.5, -2.0, 2.5)), "e.json");
  const SpringJoint g = springJoint(scene, "j");
  double drift[2];
  for (int r = 0; r < 2; ++r) {
    const double dt = r == 0 ? 4e-3 : 2e-3;
    std::vector<double> e;
    reducedAngles<2>(g, dt, static_cast<int>(std::lround(2.0 / dt)), &e);
    drift[r] = 0.0;
    for (double x : e) drift[r] = std::max(drift[r], std::abs(x - e.front()));
  }
  EXPECT_LT(drift[1], 1e-8);  // measured 1.1e-10
  EXPECT_GT(drift[0] / drift[1], 12.0);  // h⁴: 16
}

TEST(SpringJoint, RefusesWhatItCannotModel) {
  auto message = [](const std::string& text, const std::string& joint) {
    try {
      springJoint(parseScene(text, "bad.json"), joint);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string hinge = R"("axis_main": [0, 1, 0])";
  const std::string one = armScene("revolute", false, Eigen::Quaterniond::Identity(), kPivot, kAnchor, hinge,
                                   Eigen::Vector3d::Zero());
  EXPECT_NE(message(one, "nope").find("no joint 'nope'"), std::string::npos);
  EXPECT_NE(message(armScene("spherical", false, Eigen::Quaterniond::Identity(), kPivot, kAnchor, "",
                             Eigen::Vector3d::Zero()),
                    "j")
                .find(".type"),
            std::string::npos);
  std::string prescribed = armScene("revolute", false, Eigen::Quaterniond::Identity(), kPivot, kAnchor,
                                    hinge + R"(, "prescribed": {"type": "ramp", "rate": 1.0})", Eigen::Vector3d::Zero());
  EXPECT_NE(message(prescribed, "j").find("prescribed"), std::string::npos);
  // Two bodies: a double pendulum's lower joint joins two bodies, the upper
  // body is in two joints.
  const std::string dp = loadScene("double-pendulum").joints.empty() ? "" : "double-pendulum";
  ASSERT_FALSE(dp.empty());
  const SceneDescription d = loadScene(dp);
  for (const JointDescription& j : d.joints) {
    try {
      springJoint(d, j.name);
      ADD_FAILURE() << "accepted joint " << j.name;
    } catch (const InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_TRUE(what.find("joins") != std::string::npos || what.find("also in") != std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
