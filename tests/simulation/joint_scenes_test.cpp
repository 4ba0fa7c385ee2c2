/// \file
/// Scenes with joints run through the public path (parseScene / loadScene →
/// Simulation::run with a row callback, the columns of the CSV contract),
/// each against a result that does not come from lieflow: closed forms of
/// the damped torsional oscillator, the Cardan-joint speed ratio, the
/// effective inertia of geared bodies, statics of a held pendulum, and the
/// conservation laws; plus bad joint input, which must be rejected with a
/// message naming the joint and the field.
///
/// Step counts are modest: the file runs in 0.5 s of CPU in Release and in
/// about 9 s under AddressSanitizer + UBSan in a Debug -O1 build (two thirds
/// of it the 10⁵-step constraint test).
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "model/scene.hpp"
#include "simulation/simulation.hpp"
#include "liegroup/invalid_input.hpp"
#include "tests/simulation/scene_trajectory.hpp"

namespace lieflow {
namespace {

constexpr double kPi = 3.141592653589793;

using namespace scene_testing;  // NOLINT: Trajectory, simulate, num, replaced (scene_trajectory.hpp)

// --- a. Torsional spring and dashpot on a revolute joint ---------------------

// A rotation-only wheel anchored at its centre of mass on a revolute joint to
// ground (axis z), spring k and dashpot c on the joint coordinate, no gravity:
// I φ̈ = −k φ − c φ̇ with I = I_zz, the closed form
//   φ(t) = e^{−ζω t} (A cos ω_d t + B sin ω_d t),
//   ω = √(k/I), ζ = c / (2√(k I)), ω_d = ω √(1 − ζ²), A = φ₀, B = (φ̇₀ + ζω φ₀)/ω_d.
TEST(JointSceneSpringDamper, DampedOscillationMatchesClosedForm) {
  const double I = 0.4, k = 4.0, c = 0.2, phi0 = 0.3, rate0 = -1.0, T = 5.0;
  const std::string json = R"({
    "name": "spring-damper",
    "bodies": [{"name": "wheel", "mass": 2.0, "inertia": [0.3, 0.3, )" + num(I) + R"(],
                "rotation_only": true, "angular_velocity": [0, 0, )" + num(rate0) + R"(]}],
    "joints": [{"name": "hinge", "type": "revolute", "main": "ground", "secondary": "wheel",
                "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0], "axis_main": [0, 0, 1],
                "initial_angle": )" + num(phi0) + R"(,
                "spring": {"stiffness": )" + num(k) + R"(, "rest_angle": 0},
                "damper": {"damping": )" + num(c) + R"(}}]
  })";
  const Trajectory tr = simulate(parseScene(json, "spring-damper.json"), "rkmk4", 1e-3, T);
  const double w = std::sqrt(k / I), zeta = c / (2.0 * std::sqrt(k * I)), wd = w * std::sqrt(1.0 - zeta * zeta);
  const double A = phi0, B = (rate0 + zeta * w * phi0) / wd;
  double phi_err = 0.0, rate_err = 0.0, moment_err = 0.0;
  for (std::size_t r = 0; r < tr.rows.size(); ++r) {
    const double t = tr.rows[r][0];
    const double e = std::exp(-zeta * w * t), cs = std::cos(wd * t), sn = std::sin(wd * t);
    const double phi = e * (A * cs + B * sn);
    const double rate = e * ((B * wd - zeta * w * A) * cs - (A * wd + zeta * w * B) * sn);
    phi_err = std::max(phi_err, std::abs(tr.at(r, "hinge.phi") - phi));
    rate_err = std::max(rate_err, std::abs(tr.at(r, "hinge.phidot") - rate));
    // The body's own spin agrees with the joint rate (axis = body z).
    EXPECT_NEAR(tr.at(r, "wheel.wz"), tr.at(r, "hinge.phidot"), 1e-12) << "t = " << t;
    // J.moment is the moment on the main body (the ground) about the axis:
    // the reaction of the spring and dashpot moment −kφ − cφ̇ that acts on
    // the wheel, i.e. +kφ + cφ̇.
    moment_err = std::max(moment_err, std::abs(tr.at(r, "hinge.moment") -
                                               (k * tr.at(r, "hinge.phi") + c * tr.at(r, "hinge.phidot"))));
  }
  RecordProperty("phi_error", num(phi_err));
  RecordProperty("phidot_error", num(rate_err));
  // Measured (rkmk4, h = 1e-3, 5 s): 1.6e-12 rad and 5.1e-12 rad/s.
  EXPECT_LE(phi_err, 1e-10);
  EXPECT_LE(rate_err, 1e-10);
  EXPECT_LE(moment_err, 1e-12);
  // The oscillation really decays: e^{−ζω T} = 0.29.
  EXPECT_LT(std::abs(tr.rows.back()[tr.col("hinge.phi")]), 0.5 * phi0);
}

// --- b. Cardan shaft ---------------------------------------------------------

// The Cardan shaft of scenes/cardan-shaft.json with the output shaft bent by
// β: input shaft along x driven at ω₁ by prescribed motion, output shaft
// along (cos β, sin β, 0), a universal joint with the input's cross arm along
// y (in the plane of the shafts at t = 0) and the output's along z.
std::string cardanScene(double beta, double omega1, double t_end) {
  const double wout = omega1 / std::cos(beta);  // the formula at θ₁ = 0 (the projection corrects it anyway)
  return R"({
    "name": "cardan", "gravity": [0, 0, 0],
    "bodies": [
      {"name": "input", "mass": 1.0, "inertia": [0.002, 0.01, 0.01], "rotation_only": true,
       "angular_velocity": [)" + num(omega1) + R"(, 0, 0]},
      {"name": "output", "mass": 1.0, "inertia": [0.002, 0.01, 0.01], "rotation_only": true,
       "orientation": [)" + num(std::cos(beta / 2)) + ", 0, 0, " + num(std::sin(beta / 2)) + R"(],
       "angular_velocity": [)" + num(wout) + R"(, 0, 0]}],
    "joints": [
      {"name": "input-bearing", "type": "revolute", "main": "ground", "secondary": "input",
       "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0], "axis_main": [1, 0, 0],
       "prescribed": {"type": "ramp", "initial": 0, "rate": )" + num(omega1) + R"(}},
      {"name": "output-bearing", "type": "revolute", "main": "ground", "secondary": "output",
       "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0],
       "axis_main": [)" + num(std::cos(beta)) + ", " + num(std::sin(beta)) + R"(, 0], "axis_secondary": [1, 0, 0]},
      {"name": "cross", "type": "universal", "main": "input", "secondary": "output",
       "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0],
       "axis1_main": [0, 1, 0], "axis2_secondary": [0, 0, 1]}],
    "integrator": {"name": "rkmk4", "dt": 0.001}, "t_end": )" + num(t_end) + "}";
}

/// max |ω₂ − ω₁ cos β / (1 − sin²β cos²θ₁)| over the rows, θ₁ the input joint
/// angle (from the plane of the shafts), ω₂ the output joint rate; also
/// checks that the rows cover a full revolution of the input.
///
/// With the input prescribed the mechanism has no degree of freedom: the
/// state is fixed by the constraints, which the projection after each step
/// holds to 1e-12, so the error is not RK4's (it does not shrink with h) but
/// that tolerance times ∂ω₂/∂θ₁ (max 2.9 rad/s per rad at β = 30°, 21 at 60°);
/// papers/cardan-joint/ tabulates β = 15° … 75°.
double cardanError(const Trajectory& tr, double beta, double omega1) {
  double err = 0.0;
  for (std::size_t r = 0; r < tr.rows.size(); ++r) {
    const double th = tr.at(r, "input-bearing.phi");
    EXPECT_NEAR(th, omega1 * tr.rows[r][0], 1e-9);
    EXPECT_NEAR(tr.at(r, "input-bearing.phidot"), omega1, 1e-9);
    const double s = std::sin(beta), cth = std::cos(th);
    const double w2 = omega1 * std::cos(beta) / (1.0 - s * s * cth * cth);
    const double w2_sim = tr.at(r, "output-bearing.phidot");
    // The output's spin about its own shaft axis (body x) is the same rate.
    EXPECT_NEAR(tr.at(r, "output.wx"), w2_sim, 1e-9 * std::abs(w2));
    err = std::max(err, std::abs(w2_sim - w2));
  }
  EXPECT_GE(tr.at(tr.rows.size() - 1, "input-bearing.phi"), 2 * kPi);
  return err;
}

TEST(JointSceneCardan, BuiltinThirtyDegreesFollowsSpeedRatioFormula) {
  const SceneDescription scene = loadScene("cardan-shaft");
  const Trajectory tr = simulate(scene, "rkmk4", 1e-3, 0.7);  // θ₁ = 0 … 7 rad > 2π
  const double err = cardanError(tr, 30.0 * kPi / 180.0, 10.0);
  RecordProperty("max_output_speed_error", num(err));
  // Measured: 1.6e-12 rad/s (ω₂ between 8.66 and 11.55 rad/s).
  EXPECT_LE(err, 1e-10);
  EXPECT_LE(tr.result.constraint_error, 1e-12);
}

TEST(JointSceneCardan, SixtyDegreesFollowsSpeedRatioFormula) {
  const double beta = 60.0 * kPi / 180.0, omega1 = 10.0;
  const Trajectory tr = simulate(parseScene(cardanScene(beta, omega1, 0.7), "cardan60.json"), "rkmk4", 1e-3, 0.7);
  const double err = cardanError(tr, beta, omega1);
  RecordProperty("max_output_speed_error", num(err));
  // Measured: 1.0e-11 rad/s (ω₂ between 5 and 20 rad/s).
  EXPECT_LE(err, 1e-9);
  EXPECT_LE(tr.result.constraint_error, 1e-12);
}

// --- c. Gear train -----------------------------------------------------------

// scenes/gear-train.json: pinion (I₁ = 0.0015 about r₁ = body z) and wheel
// (I₂ = 0.018 about r₂ = body z) on fixed axes (carrier = ground), α = 2.
// With Δω·r = (R ω)·(R e_z) = ω_z, the row is α ω₁z + ω₂z = 0, and the
// kinetic energy is ½ (I₁ + α² I₂) ω₁² (the centres of mass do not move, so
// gravity adds a constant 0 here).
TEST(JointSceneGear, RatioHeldAndEnergyHasTheEffectiveInertia) {
  const Trajectory tr = simulate(loadScene("gear-train"), "rkmk4", 1e-3, 2.0);
  const double alpha = 2.0, I1 = 0.0015, I2 = 0.018, w1 = 10.0;
  const double energy = 0.5 * (I1 + alpha * alpha * I2) * w1 * w1;
  double row_err = 0.0, energy_err = 0.0, speed_err = 0.0;
  for (std::size_t r = 0; r < tr.rows.size(); ++r) {
    const Eigen::Vector3d o1 = tr.omega(r, "pinion"), o2 = tr.omega(r, "wheel");
    row_err = std::max(row_err, std::abs(alpha * o1.z() + o2.z()));
    // The s, t rows: no spin about the other axes.
    row_err = std::max({row_err, o1.head<2>().cwiseAbs().maxCoeff(), o2.head<2>().cwiseAbs().maxCoeff()});
    const double ke = 0.5 * (o1.dot(Eigen::Vector3d(0.001, 0.001, I1).cwiseProduct(o1)) +
                             o2.dot(Eigen::Vector3d(0.01, 0.01, I2).cwiseProduct(o2)));
    energy_err = std::max({energy_err, std::abs(ke - energy) / energy,
                           std::abs(tr.at(r, "energy") - energy) / energy});
    speed_err = std::max(speed_err, std::abs(o1.z() - w1));
  }
  RecordProperty("ratio_row_error", num(row_err));
  RecordProperty("energy_error", num(energy_err));
  // Measured: both exactly 0. Nothing loads these gears (spin about a
  // principal axis, centres of mass fixed), so the rows' reaction is 0 and
  // the speeds stay exactly 10 and −20 rad/s; the next test loads them.
  EXPECT_LE(row_err, 1e-12);
  EXPECT_LE(energy_err, 1e-12);
  EXPECT_LE(speed_err, 1e-12);
}

// Both gears on bearings to ground (the gear's s, t rows are then implied by
// the bearings and not imposed), a constant moment M on the pinion's
// bearing: (I₁ + α² I₂) ω̇₁ = M, so ω₁(t) = ω₁(0) + M t / (I₁ + α² I₂) and
// ω₂ = −α ω₁.
TEST(JointSceneGear, AppliedMomentAcceleratesTheEffectiveInertia) {
  const double alpha = 3.0, I1 = 0.002, I2 = 0.01, M = 0.05, w10 = 4.0, T = 1.0;
  const std::string json = R"({
    "name": "driven-gears", "gravity": [0, 0, -9.81],
    "bodies": [
      {"name": "pinion", "mass": 0.5, "inertia": [0.0015, 0.0015, )" + num(I1) + R"(], "rotation_only": true,
       "angular_velocity": [0, 0, )" + num(w10) + R"(]},
      {"name": "wheel", "mass": 2.0, "inertia": [0.006, 0.006, )" + num(I2) + R"(], "rotation_only": true,
       "position": [0.2, 0, 0], "angular_velocity": [0, 0, )" + num(-alpha * w10) + R"(]}],
    "joints": [
      {"name": "pinion-bearing", "type": "revolute", "main": "ground", "secondary": "pinion",
       "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0], "axis_main": [0, 0, 1], "moment": )" + num(M) + R"(},
      {"name": "wheel-bearing", "type": "revolute", "main": "ground", "secondary": "wheel",
       "anchor_main": [0.2, 0, 0], "anchor_secondary": [0, 0, 0], "axis_main": [0, 0, 1]},
      {"name": "mesh", "type": "gear", "main": "pinion", "secondary": "wheel", "ratio": )" + num(alpha) + R"(,
       "axes_main": {"r": [0, 0, 1], "s": [1, 0, 0]}, "axes_secondary": {"r": [0, 0, 1], "s": [1, 0, 0]}}]
  })";
  const Trajectory tr = simulate(parseScene(json, "driven-gears.json"), "rkmk4", 1e-3, T);
  const double Ieff = I1 + alpha * alpha * I2;
  double speed_err = 0.0, angle_err = 0.0, row_err = 0.0;
  for (std::size_t r = 0; r < tr.rows.size(); ++r) {
    const double t = tr.rows[r][0];
    speed_err = std::max(speed_err, std::abs(tr.at(r, "pinion-bearing.phidot") - (w10 + M * t / Ieff)));
    angle_err = std::max(angle_err,
                         std::abs(tr.at(r, "pinion-bearing.phi") - (w10 * t + 0.5 * M * t * t / Ieff)));
    row_err = std::max(row_err, std::abs(alpha * tr.at(r, "pinion.wz") + tr.at(r, "wheel.wz")));
  }
  RecordProperty("speed_error", num(speed_err));
  // ω₁ is linear and φ₁ quadratic in t: RK4 integrates both exactly.
  // Measured: speed error 3.1e-14 rad/s.
  EXPECT_LE(speed_err, 1e-11);
  EXPECT_LE(angle_err, 1e-11);
  EXPECT_LE(row_err, 1e-12);
  // Energy balance: the work of M is M (φ₁(T) − φ₁(0)).
  const double ke0 = 0.5 * Ieff * w10 * w10;
  const double work = M * tr.at(tr.rows.size() - 1, "pinion-bearing.phi");
  EXPECT_NEAR(tr.at(tr.rows.size() - 1, "energy") - tr.at(0, "energy"), work, 1e-11 * (ke0 + work));
}

// --- d. Rack and pinion ------------------------------------------------------

// scenes/rack-pinion.json: the pinion turns on a bearing about y (s₁ = body y)
// under M(t) = 0.2 sin 2πt, the free rack (s₂ = body x) slides; α = 0.05 m/rad.
// Row: α(Δω₁·s₁) + ΔV₂·s₂ = 0 ⇒ rack travel x − x₀ = −α (φ − φ₀). The
// effective inertia I₁ + α² m₂ gives the closed form
//   φ̇ = A (1 − cos 2πt) / (2π),  φ = A (t − sin(2πt)/(2π)) / (2π),  A = 0.2 / (I₁ + α² m₂).
TEST(JointSceneRackPinion, RackTravelIsMinusRatioTimesPinionRotation) {
  const Trajectory tr = simulate(loadScene("rack-pinion"), "rkmk4", 1e-3, 2.0);
  const double alpha = 0.05, I1 = 0.0015, m2 = 2.0;
  const double A = 0.2 / (I1 + alpha * alpha * m2), w = 2 * kPi;
  const double x0 = tr.at(0, "rack.x"), phi0 = tr.at(0, "bearing.phi");
  double rate_row = 0.0, travel = 0.0, closed_form = 0.0;
  for (std::size_t r = 0; r < tr.rows.size(); ++r) {
    const double t = tr.rows[r][0];
    // Rows in the world: Δω₁·s₁ = ω₁·(body y), ΔV₂·s₂ = v₂·(R₂ e_x), ΔV₂·t₂ = v₂·(R₂ e_y).
    const Eigen::Matrix3d R2 = tr.orientation(r, "rack").normalized().toRotationMatrix();
    const Eigen::Vector3d v2(tr.at(r, "rack.vx"), tr.at(r, "rack.vy"), tr.at(r, "rack.vz"));
    const Eigen::Vector3d o1 = tr.omega(r, "pinion");
    rate_row = std::max({rate_row, std::abs(alpha * o1.y() + v2.dot(R2.col(0))),
                         std::abs(alpha * o1.z() + v2.dot(R2.col(1)))});
    travel = std::max(travel, std::abs((tr.at(r, "rack.x") - x0) + alpha * (tr.at(r, "bearing.phi") - phi0)));
    closed_form = std::max({closed_form, std::abs(tr.at(r, "bearing.phidot") - A * (1 - std::cos(w * t)) / w),
                            std::abs(tr.at(r, "bearing.phi") - A * (t - std::sin(w * t) / w) / w)});
  }
  RecordProperty("rate_row_error", num(rate_row));
  RecordProperty("travel_error", num(travel));
  RecordProperty("closed_form_error", num(closed_form));
  // Measured: rows 5.6e-17, travel 4.4e-16 m, closed form 5.3e-12.
  EXPECT_LE(rate_row, 1e-12);
  EXPECT_LE(travel, 1e-12);
  EXPECT_LE(closed_form, 1e-10);
  // The rack has really moved: 2 periods of M move it by −α A · 2/(2π) ≈ −0.49 m.
  EXPECT_LT(tr.at(tr.rows.size() - 1, "rack.x") - x0, -0.3);
}

// --- e. Differential ---------------------------------------------------------

// scenes/differential.json: the input (r₁ = body z) is driven at ω₁ = 10 rad/s
// by prescribed motion; the outputs (I = 0.005 about z each) share it,
// α ω₁ + ω₂ + ω₃ = 0 with α = 2, and the right output has a dashpot c = 0.002.
// All start at rest; the initial projection in the mass metric splits the
// output speed equally (ω₂ = ω₃ = −10). The common gear reaction acts equally
// on both outputs, so ω̇₂ = ω̇₃ + c ω₃ / I and ω̇₂ + ω̇₃ = 0 give
//   ω₃ = −10 e^{−c t / (2I)},  ω₂ = −20 − ω₃.
TEST(JointSceneDifferential, SpeedsSumAndDashpotSplitsThem) {
  const Trajectory tr = simulate(loadScene("differential"), "rkmk4", 1e-3, 2.0);
  const double alpha = 2.0, c = 0.002, I = 0.005;
  double row_err = 0.0, input_err = 0.0, split_err = 0.0;
  for (std::size_t r = 0; r < tr.rows.size(); ++r) {
    const double t = tr.rows[r][0];
    const double w1 = tr.at(r, "input.wz"), w2 = tr.at(r, "left.wz"), w3 = tr.at(r, "right.wz");
    row_err = std::max(row_err, std::abs(alpha * w1 + w2 + w3));
    // Same relation on the joint rates (the bearings' axes are the r axes).
    row_err = std::max(row_err, std::abs(alpha * tr.at(r, "input-bearing.phidot") + tr.at(r, "left-bearing.phidot") +
                                         tr.at(r, "right-bearing.phidot")));
    input_err = std::max(input_err, std::abs(w1 - 10.0));
    const double w3_ref = -10.0 * std::exp(-c * t / (2 * I));
    split_err = std::max({split_err, std::abs(w3 - w3_ref), std::abs(w2 - (-20.0 - w3_ref))});
  }
  RecordProperty("row_error", num(row_err));
  RecordProperty("closed_form_error", num(split_err));
  // Measured: rows 8.9e-16 rad/s, closed form 4.4e-14 rad/s.
  EXPECT_LE(row_err, 1e-12);
  EXPECT_LE(input_err, 1e-12);
  EXPECT_LE(split_err, 1e-10);
  // Position level: α φ₁ + φ₂ + φ₃ stays 0 (it starts at 0).
  const std::size_t last = tr.rows.size() - 1;
  EXPECT_NEAR(alpha * tr.at(last, "input-bearing.phi") + tr.at(last, "left-bearing.phi") +
                  tr.at(last, "right-bearing.phi"),
              0.0, 1e-10);
}

// --- f. Static balance -------------------------------------------------------

// A 1 m rod (m = 1 kg, CoM 0.5 m from the hinge) on a revolute joint to
// ground about y, horizontal: joint angle π/2 from the hanging position,
// CoM at (−0.5, 0, 0). Gravity's moment on the rod about +y is
// (−L e_x) × (−m g e_z) · e_y = −m g L, so the joint must apply +m g L to the
// rod, and the moment on the ground (the main body; README: M_J = M_M · a) is
// J.moment = −m g L = −4.905 N·m. With the rod as the main body (`rod_main`:
// main and secondary swapped, the joint angle is then −π/2) J.moment is the
// moment on the rod itself, +m g L.
std::string horizontalRod(const std::string& drive, bool rod_main = false) {
  const std::string bodies = rod_main ? R"("main": "rod", "secondary": "ground",
                "anchor_main": [0, 0, 0.5], "anchor_secondary": [0, 0, 0],)"
                                      : R"("main": "ground", "secondary": "rod",
                "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.5],)";
  return R"({
    "name": "held-rod", "gravity": [0, 0, -9.81],
    "bodies": [{"name": "rod", "mass": 1.0, "inertia": [0.08333333333333333, 0.08333333333333333, 0.001],
                "orientation": [)" + num(std::cos(kPi / 4)) + ", 0, " + num(std::sin(kPi / 4)) + R"(, 0],
                "position": [-0.5, 0, 0]}],
    "joints": [{"name": "hinge", "type": "revolute", )" + bodies + R"( "axis_main": [0, 1, 0],
                "initial_angle": )" + num(rod_main ? -kPi / 2 : kPi / 2) + ", " + drive + R"(}]
  })";
}

TEST(JointSceneStatics, PrescribedHorizontalPendulumReactsGravityMoment) {
  const double mgL = 1.0 * 9.81 * 0.5;
  const Trajectory tr =
      simulate(parseScene(horizontalRod(R"("prescribed": )" + num(kPi / 2)), "held.json"), "rkmk4", 1e-3, 0.5, 10);
  double moment_err = 0.0, angle_err = 0.0;
  for (std::size_t r = 0; r < tr.rows.size(); ++r) {
    moment_err = std::max(moment_err, std::abs(tr.at(r, "hinge.moment") - (-mgL)));
    angle_err = std::max({angle_err, std::abs(tr.at(r, "hinge.phi") - kPi / 2), std::abs(tr.at(r, "rod.x") + 0.5),
                          std::abs(tr.at(r, "rod.z"))});
  }
  RecordProperty("moment_error", num(moment_err));
  // Measured: J.moment = −4.905 N·m to 8.9e-16.
  EXPECT_LE(moment_err, 1e-12);
  EXPECT_LE(angle_err, 1e-12);
  // The rod as the main body: J.moment = +m g L, the moment on the rod.
  const Trajectory swapped = simulate(
      parseScene(horizontalRod(R"("prescribed": )" + num(-kPi / 2), true), "held2.json"), "rkmk4", 1e-3, 0.5, 10);
  for (std::size_t r = 0; r < swapped.rows.size(); ++r) {
    EXPECT_NEAR(swapped.at(r, "hinge.moment"), mgL, 1e-12);
    EXPECT_NEAR(swapped.at(r, "hinge.phi"), -kPi / 2, 1e-12);
  }
}

TEST(JointSceneStatics, AppliedMomentBalancesGravity) {
  const double mgL = 1.0 * 9.81 * 0.5;
  // The applied joint moment acts +M about the axis on the secondary body (the rod).
  const Trajectory tr =
      simulate(parseScene(horizontalRod(R"("moment": )" + num(mgL)), "balanced.json"), "rkmk4", 1e-3, 1.0, 10);
  double moment_err = 0.0, angle_err = 0.0, rate_err = 0.0;
  for (std::size_t r = 0; r < tr.rows.size(); ++r) {
    moment_err = std::max(moment_err, std::abs(tr.at(r, "hinge.moment") - (-mgL)));
    angle_err = std::max(angle_err, std::abs(tr.at(r, "hinge.phi") - kPi / 2));
    rate_err = std::max(rate_err, std::abs(tr.at(r, "hinge.phidot")));
  }
  RecordProperty("angle_error", num(angle_err));
  // Measured: the rod does not move at all (angle error exactly 0), and
  // J.moment = −m g L as in the prescribed case: it is the constraint
  // reaction plus the joint's force elements, here the applied moment alone.
  EXPECT_LE(angle_err, 1e-12);
  EXPECT_LE(rate_err, 1e-12);
  EXPECT_LE(moment_err, 1e-12);
  // A moment slightly off balance lets it swing: the check above is not vacuous.
  const Trajectory off =
      simulate(parseScene(horizontalRod(R"("moment": )" + num(0.9 * mgL)), "off.json"), "rkmk4", 1e-3, 1.0, 100);
  EXPECT_GT(std::abs(off.at(off.rows.size() - 1, "hinge.phi") - kPi / 2), 0.1);
}

// --- g. Conservation ---------------------------------------------------------

TEST(JointSceneConservation, DoublePendulumEnergy) {
  // No row callback: the drift statistics alone (every step observed).
  const Simulation sim(loadScene("double-pendulum"));
  SimulationOptions o;
  o.integrator = "rkmk4";
  o.dt = 1e-3;
  o.t_end = 10.0;
  const SimulationResult r = sim.run(o);
  ASSERT_FALSE(r.failed) << r.failure;
  RecordProperty("energy_drift", num(r.energy_drift));
  RecordProperty("constraint_error", num(r.constraint_error));
  // Measured: 1.48e-9 relative (E₀ = −5.909 J). RK4 (not symplectic) plus
  // the projection conserves energy only up to its truncation error: the
  // drift is 2.3e-8, 1.5e-9, 9.4e-11 at h = 2e-3, 1e-3, 5e-4 (∝ h⁴). It is
  // not secular over these 10 s: the maximum is an excursion at t = 1.90 s,
  // where the elbow turns at 13.6 rad/s, and at t = 10 s the error is 1.4e-10.
  EXPECT_LE(r.energy_drift, 1e-8);
  // The projection after each step stops at max |Φ| ≤ 1e-12 (ProjectedStepper).
  EXPECT_LE(r.constraint_error, 1e-10);
}

TEST(JointSceneConservation, PendulumConstraintErrorOverHundredThousandSteps) {
  const Simulation sim(loadScene("pendulum"));
  SimulationOptions o;
  o.integrator = "rkmk-heun";
  o.dt = 1e-4;
  o.t_end = 10.0;  // 10⁵ steps
  const SimulationResult r = sim.run(o);
  ASSERT_FALSE(r.failed) << r.failure;
  EXPECT_EQ(r.steps, 100000);
  RecordProperty("constraint_error", num(r.constraint_error));
  RecordProperty("wall_seconds", num(r.wall_seconds));
  // Heun's method alone would let |Φ| drift by its O(h³) local error every
  // step; the projection after each step (ProjectedStepper: simplified
  // Newton until max |Φ| ≤ 1e-12, failing the run otherwise) must succeed at
  // all 10⁵ steps. Measured: max |Φ| = 1.0e-12 m. Run time: 0.32 s in
  // Release; 6.2 s of CPU (14 s wall on a loaded 2-core machine) under
  // ASan/UBSan at -O1 — the full 10⁵ steps run in every build.
  EXPECT_LE(r.constraint_error, 1e-10);
}

// --- h. Bad joint input ------------------------------------------------------

// Two bodies on revolute joints (the double pendulum), the base of the
// variants below.
const char* kTwoRods = R"({
  "name": "rods", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "upper", "mass": 1.0, "inertia": [0.08333333333333333, 0.08333333333333333, 0.001],
     "position": [0, 0, -0.5]},
    {"name": "lower", "mass": 1.0, "inertia": [0.08333333333333333, 0.08333333333333333, 0.001],
     "position": [0, 0, -1.5]}],
  "joints": [
    {"name": "shoulder", "type": "revolute", "main": "ground", "secondary": "upper",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0]},
    {"name": "elbow", "type": "revolute", "main": "upper", "secondary": "lower",
     "anchor_main": [0, 0, -0.5], "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0]}],
  "integrator": {"name": "rkmk4", "dt": 0.001}, "t_end": 0.01
})";

// Assembly errors name the joint as "joints[k] (name).field", reader errors as
// "joints[k].field": fragments are matched against the message with the
// " (name)" parts removed.
void expectRejected(const std::string& json, std::initializer_list<const char*> fragments) {
  const std::string what = std::regex_replace(rejection(json), std::regex(R"( \([^()]*\)\.)"), ".");
  EXPECT_NE(what.find("joints.json"), std::string::npos) << what;
  for (const char* f : fragments) EXPECT_NE(what.find(f), std::string::npos) << "'" << f << "' not in: " << what;
}

std::string twoRods(const std::string& from, const std::string& to) { return replaced(kTwoRods, from, to); }

TEST(JointSceneBadInput, BaseSceneIsAccepted) {
  const Simulation sim(parseScene(kTwoRods, "joints.json"));
  EXPECT_EQ(sim.columns().size(), 1u + 2 * 13 + 2 * 3 + 5);
}

TEST(JointSceneBadInput, BodiesOfAJoint) {
  expectRejected(twoRods(R"("secondary": "lower")", R"("secondary": "nobody")"),
                 {"joints[1].secondary", "unknown body 'nobody'"});
  expectRejected(twoRods(R"("secondary": "lower")", R"("secondary": "upper")"),
                 {"joints[1].secondary", "itself"});
}

TEST(JointSceneBadInput, Axes) {
  expectRejected(twoRods(R"("axis_main": [0, 1, 0]}])", R"("axis_main": [0, 0, 0]}])"),
                 {"joints[1].axis_main", "zero"});
  // JSON has no NaN/Inf: an overflowing number is rejected by the parser...
  expectRejected(twoRods(R"("axis_main": [0, 1, 0]}])", R"("axis_main": [0, 1e999, 0]}])"), {"not valid JSON"});
  // ...and a non-finite axis given to the Simulation constructor names the joint and field.
  SceneDescription s = parseScene(kTwoRods, "joints.json");
  s.joints[1].axis_main.y() = std::numeric_limits<double>::quiet_NaN();
  try {
    const Simulation sim(s);
    ADD_FAILURE() << "a NaN axis was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("joints[1]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("axis_main"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos) << e.what();
  }
  // 1e-3 off unit is rejected, 1e-7 off is normalized.
  expectRejected(twoRods(R"("axis_main": [0, 1, 0]}])", R"("axis_main": [0, 1.001, 0]}])"),
                 {"joints[1].axis_main", "not within"});
  const Trajectory exact = simulate(parseScene(kTwoRods, "joints.json"), "rkmk4", 1e-3, 0.01);
  const Trajectory near = simulate(
      parseScene(twoRods(R"("axis_main": [0, 1, 0]}])", R"("axis_main": [0, 1.0000001, 0]}])"), "joints.json"), "rkmk4",
      1e-3, 0.01);
  ASSERT_EQ(exact.rows.size(), near.rows.size());
  for (std::size_t i = 0; i < exact.rows.back().size(); ++i)
    EXPECT_NEAR(near.rows.back()[i], exact.rows.back()[i], 1e-14) << exact.columns[i];
}

TEST(JointSceneBadInput, UniversalAxesNotOrthogonal) {
  const std::string cardan = cardanScene(30.0 * kPi / 180.0, 10.0, 0.1);
  expectRejected(replaced(cardan, R"("axis2_secondary": [0, 0, 1])", R"("axis2_secondary": [0, 0.1, 0.99498743710662])"),
                 {"joints[2].axis2_secondary", "not orthogonal"});
}

TEST(JointSceneBadInput, Gears) {
  const std::string base = R"({
    "name": "g",
    "bodies": [{"name": "a", "mass": 1, "inertia": [1, 1, 1], "rotation_only": true},
               {"name": "b", "mass": 1, "inertia": [1, 1, 1], "rotation_only": true}],
    "joints": [{"name": "mesh", "type": "gear", "main": "a", "secondary": "b", "ratio": 2,
                "axes_main": {"r": [0, 0, 1], "s": [1, 0, 0]}, "axes_secondary": {"r": [0, 0, 1], "s": [1, 0, 0]}}]
  })";
  EXPECT_NO_THROW(Simulation(parseScene(base, "joints.json")));
  expectRejected(replaced(base, R"("ratio": 2)", R"("ratio": 0)"), {"joints[0].ratio", "0"});
  expectRejected(replaced(base, R"("secondary": "b")", R"("secondary": "ground")"),
                 {"joints[0].secondary", "rotary inertia"});
  expectRejected(replaced(base, R"("main": "a")", R"("main": "ground")"), {"joints[0].main", "rotary inertia"});
  // s tilted by 0.01 rad towards r (unit, but not orthogonal to r).
  expectRejected(replaced(base, R"("s": [1, 0, 0]})",
                          R"("s": [)" + num(std::cos(0.01)) + ", 0, " + num(std::sin(0.01)) + "]}"),
                 {"joints[0].axes_main.s", "orthogonal"});
}

TEST(JointSceneBadInput, RedundantJointIsNamed) {
  // A second, identical hinge between ground and the upper rod.
  const std::string json = twoRods(
      R"({"name": "elbow")",
      R"({"name": "shoulder-again", "type": "revolute", "main": "ground", "secondary": "upper",
          "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0]},
         {"name": "elbow")");
  const std::string what = rejection(json);
  EXPECT_NE(what.find("joints.json"), std::string::npos) << what;
  EXPECT_NE(what.find("shoulder"), std::string::npos) << what;
  EXPECT_NE(what.find("redundant"), std::string::npos) << what;
}

TEST(JointSceneBadInput, AnchorsMustCoincide) {
  expectRejected(twoRods(R"("anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0]}])",
                         R"("anchor_secondary": [0, 0, 0.6], "axis_main": [0, 1, 0]}])"),
                 {"joints[1].anchor_secondary", "do not coincide"});
}

TEST(JointSceneBadInput, UnknownFieldInAJoint) {
  expectRejected(twoRods(R"("name": "elbow",)", R"("name": "elbow", "colour": "red",)"),
                 {"joints[1].colour", "unknown field"});
}

TEST(JointSceneBadInput, TimeFunctions) {
  expectRejected(twoRods(R"("name": "elbow",)", R"("name": "elbow", "moment": {"type": "square", "value": 1},)"),
                 {"joints[1].moment.type", "unknown time function 'square'"});
  expectRejected(twoRods(R"("name": "elbow",)",
                         R"("name": "elbow", "prescribed": {"type": "table", "points": [[0, 0], [1, 1], [1, 2]]},)"),
                 {"joints[1].prescribed.points[2]", "increase"});
  expectRejected(twoRods(R"("name": "elbow",)", R"("name": "elbow", "moment": {"type": "sine", "amplitude": 1},)"),
                 {"joints[1].moment.frequency", "missing"});
}

TEST(JointSceneBadInput, SpringOnASphericalJoint) {
  const std::string json = twoRods(
      R"("type": "revolute", "main": "upper")",
      R"("type": "spherical", "spring": {"stiffness": 1}, "main": "upper")");
  const std::string spherical = replaced(json, R"(, "axis_main": [0, 1, 0]}],)", "}],");
  // A spherical joint has no joint coordinate: the reader does not know the field.
  expectRejected(spherical, {"joints[1].spring"});
}

}  // namespace
}  // namespace lieflow
