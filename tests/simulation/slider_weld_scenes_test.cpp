/// \file
/// Scenes with prismatic and fixed joints through the public path
/// (parseScene / loadScene → Simulation::run, the CSV contract's columns),
/// each against a result that does not come from lieflow:
///  * a mass on a tilted prismatic joint with a spring and a dashpot under
///    gravity: the closed form of the damped oscillator, in every
///    constrained integrator;
///  * the built-in slider-crank: the slider's position and speed against the
///    closed form of the crank angle, the weld's reaction against Newton's
///    law for the counterweight, conserved energy;
///  * a prescribed slide: the joint force against m (ẍ + g);
///  * a pendulum of two welded bodies against the one rigid body they make
///    (mass, centre and inertia combined by hand: the parallel-axis theorem);
///  * bad input named by file, joint and field.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "dynamics/joint_space/articulated_scene.hpp"
#include "model/scene.hpp"
#include "simulation/simulation.hpp"
#include "liegroup/invalid_input.hpp"
#include "tests/simulation/scene_trajectory.hpp"

namespace lieflow {
namespace {

using namespace scene_testing;  // NOLINT: Trajectory, simulate, num, replaced (scene_trajectory.hpp)

constexpr double kGravity = 9.81;

// --- a. Spring-mass on a prismatic joint ---------------------------------------

/// A block of mass m on a prismatic joint to ground along a = (0.6, 0, 0.8),
/// spring k (rest 0.1 m) and dashpot c, gravity −9.81 z, released at x = 0:
///   m ẍ = −k (x − x_r) − c ẋ + m g·a,   x_e = x_r + m g·a / k,
///   x(t) = x_e + e^{−ζωt} (A cos ω_d t + B sin ω_d t),  A = x₀ − x_e, B = ζω A / ω_d.
struct SpringMass {
  double m = 2.0, k = 50.0, c = 0.0, rest = 0.1;
  Eigen::Vector3d axis = Eigen::Vector3d(0.6, 0.0, 0.8);

  std::string json() const {
    return R"({"name": "spring-mass", "gravity": [0, 0, -9.81],
      "bodies": [{"name": "block", "mass": )" + num(m) + R"(, "inertia": [0.01, 0.02, 0.03],
                  "orientation": [0.9238795325112867, 0.3826834323650898, 0, 0], "position": [1, 2, 3]}],
      "joints": [{"name": "slide", "type": "prismatic", "main": "ground", "secondary": "block",
                  "anchor_main": [1.1, 2, 3], "anchor_secondary": [0.1, 0, 0],
                  "axis_main": [0.6, 0, 0.8],
                  "spring": {"stiffness": )" + num(k) + R"(, "rest_position": )" + num(rest) + R"(},
                  "damper": {"damping": )" + num(c) + R"(}}]})";
  }
  double x(double t) const {
    const double w = std::sqrt(k / m), zeta = c / (2.0 * std::sqrt(k * m)), wd = w * std::sqrt(1.0 - zeta * zeta);
    const double xe = rest + m * (-kGravity * axis.z()) / k;
    const double A = 0.0 - xe, B = zeta * w * A / wd;
    return xe + std::exp(-zeta * w * t) * (A * std::cos(wd * t) + B * std::sin(wd * t));
  }
};

TEST(PrismaticSpringMass, EveryConstrainedIntegratorFollowsTheClosedForm) {
  for (const double c : {0.0, 3.0}) {
    SpringMass s;
    s.c = c;
    const SceneDescription scene = parseScene(s.json(), "spring-mass.json");
    struct Case {
      const char* integrator;
      double dt, tolerance;
    };
    // Fourth-order methods to 1e-9 m, cg3 to 1e-7 m; second-order ones
    // (h = 1e-3, ω = 5) to 2e-5 m of a 0.2 m amplitude.
    for (const Case& k : {Case{"rkmk4", 1e-3, 1e-9}, Case{"cf4", 1e-3, 1e-9}, Case{"cg3", 1e-3, 1e-7},
                          Case{"lgvi", 1e-3, 2e-5}, Case{"genalpha", 1e-3, 2e-5}}) {
      SCOPED_TRACE(std::string(k.integrator) + " c = " + num(c));
      const Trajectory tr = simulate(scene, k.integrator, k.dt, 2.0, 10);
      double err = 0.0, off = 0.0;
      for (std::size_t r = 0; r < tr.rows.size(); ++r) {
        const double t = tr.rows[r][0];
        err = std::max(err, std::abs(tr.at(r, "slide.x") - s.x(t)));
        // The block keeps its orientation and its anchor stays on the line.
        off = std::max(off, tr.orientation(r, "block").angularDistance(
                                Eigen::Quaterniond(0.9238795325112867, 0.3826834323650898, 0, 0)));
        const Eigen::Vector3d p(tr.at(r, "block.x"), tr.at(r, "block.y"), tr.at(r, "block.z"));
        const Eigen::Vector3d d = p - Eigen::Vector3d(1.0, 2.0, 3.0);
        off = std::max(off, (d - d.dot(s.axis) * s.axis).norm());
        EXPECT_NEAR(d.dot(s.axis), tr.at(r, "slide.x"), 1e-12);
      }
      std::cout << "[ measured ] " << k.integrator << " c = " << c << ": max |x − x_exact| = " << err
                << " m, off the slide " << off << "\n";
      EXPECT_LE(err, k.tolerance);
      EXPECT_LE(off, 1e-11);
    }
  }
}

TEST(PrismaticSpringMass, EnergyWithoutDampingIsConserved) {
  const SceneDescription scene = parseScene(SpringMass().json(), "spring-mass.json");
  const Trajectory tr = simulate(scene, "lgvi", 1e-3, 20.0, 100);
  // E = ½ m ẋ² + ½ k (x − x_r)² − m g·a x (block's potential), so the
  // scene's energy column must stay at its t = 0 value.
  EXPECT_LE(tr.result.energy_drift, 1e-5);
  const SpringMass s;
  const double x = tr.at(tr.rows.size() - 1, "slide.x"), v = tr.at(tr.rows.size() - 1, "slide.xdot");
  const double E = 0.5 * s.m * v * v + 0.5 * s.k * (x - s.rest) * (x - s.rest) + s.m * kGravity * s.axis.z() * x;
  const double E0 = 0.5 * s.k * s.rest * s.rest;
  EXPECT_NEAR(E, E0, 1e-5 * std::abs(E0) + 1e-9);
}

// --- b. The built-in slider-crank --------------------------------------------

TEST(SliderCrank, SliderFollowsTheCrankAngleAndTheWeldCarriesTheCounterweight) {
  const double r = 0.1, l = 0.3, m_cw = 0.4, r_cw = 0.05;
  const Trajectory tr = simulate(loadScene("slider-crank"), "rkmk4", 1e-3, 1.0);
  double x_err = 0.0, v_err = 0.0, f_err = 0.0;
  for (std::size_t i = 0; i < tr.rows.size(); ++i) {
    const double th = tr.at(i, "bearing.phi"), w = tr.at(i, "bearing.phidot");
    const double root = std::sqrt(l * l - r * r * std::sin(th) * std::sin(th));
    const double x = r * std::cos(th) + root - (r + l);
    const double v = -r * w * std::sin(th) - r * r * w * std::sin(th) * std::cos(th) / root;
    x_err = std::max(x_err, std::abs(tr.at(i, "guide.x") - x));
    v_err = std::max(v_err, std::abs(tr.at(i, "guide.xdot") - v));
    // The counterweight turns with the crank about z at r_cw: in the crank's
    // frame the weld pulls it inward by m ω² r_cw and holds it up by m g.
    f_err = std::max({f_err, std::abs(tr.at(i, "weld.fx") - m_cw * w * w * r_cw),
                      std::abs(tr.at(i, "weld.fz") - m_cw * kGravity), std::abs(tr.at(i, "weld.mx")),
                      std::abs(tr.at(i, "weld.my"))});
  }
  std::cout << "[ measured ] slider-crank: slider x " << x_err << " m, speed " << v_err << " m/s, weld reaction "
            << f_err << " N (N m) from the closed forms\n";
  EXPECT_LE(x_err, 1e-10);
  EXPECT_LE(v_err, 1e-9);
  EXPECT_LE(f_err, 1e-8);
  EXPECT_GT(tr.at(tr.rows.size() - 1, "bearing.phi"), 2 * M_PI);  // through both dead centres
  EXPECT_LE(tr.result.energy_drift, 1e-7);
}

TEST(SliderCrank, EnergyIsConservedByEveryConstrainedIntegrator) {
  const SceneDescription scene = loadScene("slider-crank");
  for (const char* integrator : {"rkmk4", "cf4", "lgvi", "genalpha"}) {
    SCOPED_TRACE(integrator);
    const Trajectory tr = simulate(scene, integrator, 1e-3, 2.0, 100);
    std::cout << "[ measured ] slider-crank " << integrator << ": energy drift " << tr.result.energy_drift
              << ", constraint error " << tr.result.constraint_error << "\n";
    EXPECT_LE(tr.result.energy_drift, 1e-3);
    EXPECT_LE(tr.result.constraint_error, 1e-9);
  }
}

TEST(SliderCrank, WeldsInJointCoordinatesFollowTheMaximalFormulation) {
  // The weld is a tree joint without a coordinate (articulated_model.hpp,
  // kFixed): the counterweight moves with the crank, its inertia joins the
  // crank's articulated inertia, and J.fx … J.mz are the force the
  // articulated-body algorithm passes across it. Every column against the
  // maximal formulation (the weld's six rows with multipliers) after 0.5 s
  // at h = 1e-4, rkmk4; a body's quaternion up to its sign (each formulation
  // keeps its own). Measured 1.2e-12 (the weld's force).
  const SceneDescription scene = loadScene("slider-crank");
  const Simulation sim(scene);
  EXPECT_EQ(sim.defaultFormulation("rkmk4"), "joint");
  EXPECT_EQ(sim.defaultFormulation("lgvi"), "joint");
  const Trajectory joint = simulate(scene, "rkmk4", 1e-4, 0.5, 1000, "joint");
  const Trajectory maximal = simulate(scene, "rkmk4", 1e-4, 0.5, 1000, "maximal");
  ASSERT_EQ(joint.columns, maximal.columns);
  ASSERT_EQ(joint.rows.size(), maximal.rows.size());
  double worst = 0.0;
  for (std::size_t r = 0; r < joint.rows.size(); ++r)
    for (std::size_t c = 1; c < joint.columns.size(); ++c) {
      const std::string& name = joint.columns[c];
      if (name.size() > 3 && name.compare(name.size() - 3, 3, ".qw") == 0) {
        // The four components of a quaternion, with the sign that matches.
        double same = 0.0, flipped = 0.0;
        for (int k = 0; k < 4; ++k) {
          same = std::max(same, std::abs(joint.rows[r][c + k] - maximal.rows[r][c + k]));
          flipped = std::max(flipped, std::abs(joint.rows[r][c + k] + maximal.rows[r][c + k]));
        }
        worst = std::max(worst, std::min(same, flipped));
        c += 3;
        continue;
      }
      worst = std::max(worst, std::abs(joint.rows[r][c] - maximal.rows[r][c]) / std::max(1.0, std::abs(maximal.rows[r][c])));
    }
  std::cout << "[ measured ] slider-crank, joint against maximal coordinates over 0.5 s: " << worst << "\n";
  EXPECT_LT(worst, 1e-10);
}

// --- c. A prescribed slide: the joint force ---------------------------------------

TEST(PrismaticDrive, ForceOfAPrescribedVerticalSlide) {
  // x(t) = A sin 2πft on a vertical guide: the joint pushes the block up by
  // m (ẍ + g), so the force on the main body (ground) along z is −m (ẍ + g).
  const double m = 1.5, A = 0.2, f = 1.0, w = 2 * M_PI * f;
  const std::string json = R"({"name": "lift", "gravity": [0, 0, -9.81],
    "bodies": [{"name": "block", "mass": 1.5, "inertia": [0.01, 0.01, 0.01], "position": [0, 0, 0],
                "velocity": [0, 0, )" + num(A * w) + R"(]}],
    "joints": [{"name": "lift", "type": "prismatic", "main": "ground", "secondary": "block",
                "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0], "axis_main": [0, 0, 1],
                "prescribed": {"type": "sine", "amplitude": 0.2, "frequency": 1}}]})";
  const Trajectory tr = simulate(parseScene(json, "lift.json"), "rkmk4", 1e-3, 1.0, 10);
  double err = 0.0;
  for (std::size_t i = 0; i < tr.rows.size(); ++i) {
    const double t = tr.rows[i][0];
    EXPECT_NEAR(tr.at(i, "lift.x"), A * std::sin(w * t), 1e-12);
    EXPECT_NEAR(tr.at(i, "lift.xdot"), A * w * std::cos(w * t), 1e-9);
    err = std::max(err, std::abs(tr.at(i, "lift.force") + m * (-A * w * w * std::sin(w * t) + kGravity)));
  }
  EXPECT_LE(err, 1e-8);
}

// --- d. Two welded bodies swing as one ------------------------------------------------

TEST(FixedJoint, WeldedPendulumSwingsAsTheMergedBody) {
  // A rod (1 kg, centre 0.5 m below the pivot) and a block (0.5 kg, turned
  // 30° about x, at (0.1, 0, −1)) welded to it, on a hinge about y; against
  // one body with their combined mass, centre and inertia (world axes):
  //   c = Σ m_i p_i / m,  I = Σ R_i I_i R_iᵀ + m_i (|d_i|² 1 − d_i d_iᵀ),  d_i = p_i − c.
  const double m1 = 1.0, m2 = 0.5, w0 = 1.5;
  const Eigen::Vector3d p1(0, 0, -0.5), p2(0.1, 0, -1.0), I1(0.08, 0.08, 0.002), I2(0.002, 0.003, 0.004);
  const Eigen::Quaterniond q2(Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitX()));
  const Eigen::Vector3d w(0, w0, 0);
  auto vec = [](const Eigen::Vector3d& v) { return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]"; };
  const std::string welded = R"({"name": "welded", "gravity": [0, 0, -9.81],
    "bodies": [{"name": "rod", "mass": 1, "inertia": )" + vec(I1) + R"(, "position": )" + vec(p1) +
                             R"(, "angular_velocity": )" + vec(w) + R"(, "velocity": )" + vec(w.cross(p1)) + R"(},
               {"name": "block", "mass": 0.5, "inertia": )" + vec(I2) + R"(, "position": )" + vec(p2) +
                             R"(, "orientation": [)" + num(q2.w()) + ", " + num(q2.x()) + ", 0, 0]" +
                             R"(, "angular_velocity": )" + vec(q2.inverse() * w) + R"(, "velocity": )" +
                             vec(w.cross(p2)) + R"(}],
    "joints": [{"name": "hinge", "type": "revolute", "main": "ground", "secondary": "rod",
                "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0]},
               {"name": "weld", "type": "fixed", "main": "rod", "secondary": "block",
                "anchor_main": [0.1, 0, -0.5], "anchor_secondary": [0, 0, 0]}]})";
  const double m = m1 + m2;
  const Eigen::Vector3d c = (m1 * p1 + m2 * p2) / m;
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  const Eigen::Matrix3d R2 = q2.toRotationMatrix();
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector3d d = (i == 0 ? p1 : p2) - c;
    const double mi = i == 0 ? m1 : m2;
    I += (i == 0 ? Eigen::Matrix3d(I1.asDiagonal()) : Eigen::Matrix3d(R2 * I2.asDiagonal() * R2.transpose())) +
         mi * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  std::string inertia = "[";
  for (int r = 0; r < 3; ++r) inertia += (r ? ", " : "") + vec(I.row(r).transpose());
  inertia += "]";
  const std::string merged = R"({"name": "merged", "gravity": [0, 0, -9.81],
    "bodies": [{"name": "rod", "mass": )" + num(m) + R"(, "inertia": )" + inertia + R"(, "position": )" + vec(c) +
                             R"(, "angular_velocity": )" + vec(w) + R"(, "velocity": )" + vec(w.cross(c)) + R"(}],
    "joints": [{"name": "hinge", "type": "revolute", "main": "ground", "secondary": "rod",
                "anchor_main": [0, 0, 0], "anchor_secondary": )" + vec(-c) + R"(, "axis_main": [0, 1, 0]}]})";
  const Trajectory a = simulate(parseScene(welded, "welded.json"), "rkmk4", 1e-3, 2.0, 10);
  const Trajectory b = simulate(parseScene(merged, "merged.json"), "rkmk4", 1e-3, 2.0, 10);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  double err = 0.0;
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    err = std::max({err, std::abs(a.at(i, "hinge.phi") - b.at(i, "hinge.phi")),
                    std::abs(a.at(i, "hinge.phidot") - b.at(i, "hinge.phidot")),
                    std::abs(a.at(i, "hinge.moment") - b.at(i, "hinge.moment"))});
  }
  std::cout << "[ measured ] welded pair vs merged body: max |Δφ|, |Δφ̇|, |ΔM| = " << err << "\n";
  EXPECT_LE(err, 1e-9);
  EXPECT_GT(std::abs(a.at(a.rows.size() - 1, "hinge.phi")), 0.1);  // it swung
}

// --- e. Bad input ------------------------------------------------------------------

TEST(SliderWeldBadInput, IsNamedByFileJointAndField) {
  const std::string base = SpringMass().json();
  auto expect = [&](const std::string& from, const std::string& to, std::initializer_list<const char*> parts) {
    const std::string what = rejection(replaced(base, from, to));
    for (const char* p : parts) EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' not in: " << what;
  };
  expect(R"("anchor_secondary": [0.1, 0, 0])", R"("anchor_secondary": [0.1, 0.2, 0])",
         {"joints.json", "slide", "anchor_secondary", "not on the slide axis"});
  expect(R"("axis_main": [0.6, 0, 0.8])", R"("axis_main": [0, 0, 0])", {"joints.json", "axis_main", "zero"});
  expect(R"("rest_position")", R"("rest_angle")", {"joints.json", "spring", "rest_angle"});
  expect(R"("inertia": [0.01, 0.02, 0.03])", R"("inertia": [0.01, 0.02, 0.03], "rotation_only": true)",
         {"joints.json", "secondary", "rotation_only"});
  expect(R"("type": "prismatic")", R"("type": "fixed")", {"joints.json", "spring", "no joint coordinate"});
  expect(R"("type": "prismatic")", R"("type": "slider")", {"joints.json", "type", "prismatic, fixed"});
}

TEST(SliderWeldBadInput, JointCoordinatesRefuseAWeldedHeldBodyWithTheReason) {
  // A weld is a tree joint without a coordinate (WeldsInJointCoordinates...
  // below), but a rotation-only body welded to a body that carries it turns
  // about its own held centre: maximal coordinates only.
  SceneDescription scene = loadScene("slider-crank");
  for (BodyDescription& b : scene.bodies)
    if (b.name == "counterweight") b.rotation_only = true;
  std::string why;
  EXPECT_FALSE(articulatedCovers(scene, &why));
  EXPECT_NE(why.find("welds the rotation-only body 'counterweight'"), std::string::npos) << why;
}

}  // namespace
}  // namespace lieflow
