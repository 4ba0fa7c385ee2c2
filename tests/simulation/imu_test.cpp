// Accelerometer rows (simulate --imu, SimulationOptions::imu): B.ax, B.ay,
// B.az is the specific force f = Rᵀ(a_s − g) at the body's sensor point s.
// Independent references: the closed form of a rod released from rest, and
// central differences of the sensor point's velocity taken from the
// trajectory's own rows (v_s = v_c + R (ω × s)), f ≈ Rᵀ((v_s(t+h) −
// v_s(t−h))/2h − g), on every kind of system a scene assembles into (a free
// body, a rotor about a pivot, a free rotor, multibody systems in maximal and
// in joint coordinates, rotation-only bodies included); then the noise
// options on those columns.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "app/recording_noise.hpp"
#include "model/scene.hpp"
#include "simulation/simulation.hpp"

namespace lieflow {
namespace {

struct Rows {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  int column(const std::string& name) const {
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name) return static_cast<int>(i);
    return -1;
  }
};

Rows run(const Simulation& sim, const std::string& formulation, double dt, double t_end) {
  SimulationOptions o;
  o.integrator = "rkmk4";
  o.formulation = formulation;
  o.dt = dt;
  o.t_end = t_end;
  o.imu = true;
  Rows r;
  r.columns = sim.columns(true);
  const SimulationResult result = sim.run(o, [&](const std::vector<double>& row) { r.rows.push_back(row); });
  EXPECT_FALSE(result.failed) << result.failure;
  return r;
}

Eigen::Vector3d vec(const Rows& r, std::size_t k, const std::string& body, const char* a, const char* b,
                    const char* c) {
  const std::vector<double>& row = r.rows[k];
  const int i = r.column(body + "." + a), j = r.column(body + "." + b), l = r.column(body + "." + c);
  if (i < 0) return Eigen::Vector3d::Zero();
  return Eigen::Vector3d(row[i], row[j], row[l]);
}

Eigen::Matrix3d rotation(const Rows& r, std::size_t k, const std::string& body) {
  const std::vector<double>& row = r.rows[k];
  const int i = r.column(body + ".qw");
  return Eigen::Quaterniond(row[i], row[i + 1], row[i + 2], row[i + 3]).normalized().toRotationMatrix();
}

/// Largest |f_rows − f_differences| over the interior rows and the bodies,
/// relative to the largest |f|.
double differenceCheck(const SceneDescription& scene, const std::string& formulation, double dt, double t_end) {
  const Simulation sim(scene);
  const Rows r = run(sim, formulation, dt, t_end);
  double worst = 0.0, scale = 0.0;
  for (const BodyDescription& b : scene.bodies) {
    auto sensorVelocity = [&](std::size_t k) {
      return Eigen::Vector3d(vec(r, k, b.name, "vx", "vy", "vz") +
                             rotation(r, k, b.name) * vec(r, k, b.name, "wx", "wy", "wz").cross(b.sensor));
    };
    for (std::size_t k = 1; k + 1 < r.rows.size(); ++k) {
      const Eigen::Vector3d a_s = (sensorVelocity(k + 1) - sensorVelocity(k - 1)) / (2.0 * dt);
      const Eigen::Vector3d expected = rotation(r, k, b.name).transpose() * (a_s - scene.gravity);
      const Eigen::Vector3d f = vec(r, k, b.name, "ax", "ay", "az");
      worst = std::max(worst, (f - expected).norm());
      scale = std::max(scale, f.norm());
    }
  }
  return worst / scale;
}

SceneDescription withSensors(SceneDescription scene, const std::vector<Eigen::Vector3d>& sensors) {
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) scene.bodies[i].sensor = sensors[i % sensors.size()];
  return scene;
}

TEST(Imu, RodReleasedFromRestReadsTheClosedForm) {
  // A uniform rod of length L on a hinge at its end, at rest at angle θ from
  // the downward vertical: α = (3g / 2L) sin θ, so at its centre of mass
  // (a = (3g/4) sin θ across the rod) the specific force is g cos θ along the
  // rod, towards the hinge, and −(g/4) sin θ across it (body axes: z along
  // the rod, x across).
  const SceneDescription scene = loadScene("pendulum");
  const double g = 9.81, theta = 1.0;
  for (const char* formulation : {"maximal", "joint"}) {
    const Rows r = run(Simulation(scene), formulation, 1e-3, 0.001);
    const Eigen::Vector3d f = vec(r, 0, "rod", "ax", "ay", "az");
    EXPECT_NEAR(f.x(), -0.25 * g * std::sin(theta), 1e-12) << formulation;
    EXPECT_NEAR(f.y(), 0.0, 1e-12) << formulation;
    EXPECT_NEAR(f.z(), g * std::cos(theta), 1e-12) << formulation;
  }
}

TEST(Imu, BodyAtRestReadsMinusGravity) {
  // The double pendulum hanging straight down at rest: every point at rest,
  // f = −Rᵀ g = +9.81 along the upward direction in body axes.
  SceneDescription scene = loadScene("chain-2");
  scene.gravity = Eigen::Vector3d(9.81, 0.0, 0.0);  // the chain lies along +x: hanging
  scene = withSensors(scene, {Eigen::Vector3d(0.1, 0.02, -0.03)});
  for (const char* formulation : {"maximal", "joint"}) {
    const Rows r = run(Simulation(scene), formulation, 1e-3, 0.01);
    for (const char* body : {"rod0", "rod1"}) {
      const Eigen::Vector3d f = vec(r, r.rows.size() - 1, body, "ax", "ay", "az");
      EXPECT_LT((f - Eigen::Vector3d(-9.81, 0.0, 0.0)).norm(), 1e-12) << formulation << " " << body;
    }
  }
}

TEST(Imu, MatchesDifferencesOfTheSensorVelocity) {
  const std::vector<Eigen::Vector3d> sensors = {Eigen::Vector3d(0.1, 0.05, -0.02), Eigen::Vector3d(-0.03, 0.2, 0.1)};
  // A rotor about a pivot spinning at 150 rad/s (h small for its jerk).
  EXPECT_LT(differenceCheck(withSensors(loadScene("heavy-top"), sensors), "", 1e-5, 0.004), 1e-6);
  // A rotation-only free rotor (its centre held).
  EXPECT_LT(differenceCheck(withSensors(loadScene("dzhanibekov"), sensors), "", 1e-4, 0.3), 1e-6);
  // A free body under gravity, tumbling.
  const SceneDescription free_body = withSensors(
      parseScene(R"({"name": "thrown", "gravity": [0, 0, -9.81], "bodies": [{"name": "box", "mass": 2,
                    "inertia": [0.1, 0.2, 0.25], "position": [0, 0, 1], "velocity": [1, 0, 3],
                    "angular_velocity": [3, -1, 5]}]})",
                 "thrown.json"),
      sensors);
  EXPECT_LT(differenceCheck(free_body, "", 1e-4, 0.3), 1e-6);
  // Multibody systems in both formulations: a chaotic double pendulum, a
  // rotation-only pair on a hinge with a spring and a sine moment, a chain.
  for (const char* name : {"double-pendulum", "hinge-pair", "chain-3"})
    for (const char* formulation : {"maximal", "joint"})
      EXPECT_LT(differenceCheck(withSensors(loadScene(name), sensors), formulation, 1e-4, 0.3), 1e-6)
          << name << " " << formulation;
}

TEST(Imu, NoiseAndBiasOnTheRows) {
  const Simulation sim(withSensors(loadScene("double-pendulum"), {Eigen::Vector3d(0.1, 0, 0)}));
  const Rows clean = run(sim, "maximal", 1e-3, 2.0);
  app::NoiseOptions options;
  options.acc = 0.2;
  options.gyro_bias = 0.01;
  options.seed = 7;
  app::RecordingNoise noise(clean.columns, options);
  ASSERT_TRUE(noise.hasAccelerometerColumns());
  ASSERT_EQ(noise.gyroBiases().size(), 6u);  // two bodies, three axes
  double sum = 0.0, sum2 = 0.0;
  long n = 0;
  for (const std::vector<double>& row : clean.rows) {
    std::vector<double> noisy = row;
    noise.apply(&noisy);
    for (std::size_t i = 0; i < row.size(); ++i) {
      const std::string& c = clean.columns[i];
      const double d = noisy[i] - row[i];
      if (c.size() > 3 && (c.compare(c.size() - 3, 3, ".ax") == 0 || c.compare(c.size() - 3, 3, ".az") == 0)) {
        sum += d;
        sum2 += d * d;
        ++n;
      } else if (c == "upper.wy") {
        EXPECT_NEAR(d, noise.gyroBiases()[1], 1e-12);  // constant in every row
      } else if (c.find(".w") == std::string::npos && c.find(".ay") == std::string::npos) {
        EXPECT_EQ(d, 0.0) << c;
      }
    }
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(sd, 0.2, 0.2 * 5.0 / std::sqrt(2.0 * n));  // 5 standard errors of the estimate
  EXPECT_NEAR(mean, 0.0, 5.0 * 0.2 / std::sqrt(static_cast<double>(n)));
}

}  // namespace
}  // namespace lieflow
