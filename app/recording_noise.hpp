/// \file
/// Synthetic measurement noise on trajectory rows, so that `lieflow simulate`
/// writes recordings for `lieflow calibrate` (README "Recordings"):
///   --noise-gyro σ   (rad/s)  every B.wx, B.wy, B.wz + N(0, σ²), independently;
///   --noise-angle σ  (rad)    every joint angle J.phi, J.phi1, J.phi2 + N(0, σ²);
///   --noise-quat σ   (rad)    every body quaternion q ← q ⊗ exp(δ), δ ~ N(0, σ² I₃)
///                             a body-frame rotation (the angle error has RMS √3 σ),
///                             written with q_w ≥ 0;
///   --noise-acc σ    (m/s²)   every B.ax, B.ay, B.az (--imu) + N(0, σ²);
///   --bias-gyro σ    (rad/s)  one constant bias per gyroscope axis, drawn once
///                             from N(0, σ²) before any row, added to every row;
///   --seed N                  seed of the std::mt19937_64 generator (default 1).
/// Only the written rows are perturbed; the simulation and --stats are not.
/// Rates J.phidot and positions are left exact.
#pragma once

#include <random>
#include <string>
#include <vector>

namespace lieflow {
namespace app {

struct NoiseOptions {
  double gyro = 0.0;
  double angle = 0.0;
  double quaternion = 0.0;
  double acc = 0.0;
  double gyro_bias = 0.0;
  unsigned long long seed = 1;
  bool any() const { return gyro > 0.0 || angle > 0.0 || quaternion > 0.0 || acc > 0.0 || gyro_bias > 0.0; }
};

class RecordingNoise {
 public:
  RecordingNoise(const std::vector<std::string>& columns, const NoiseOptions& options);
  /// Adds the noise to one row (same column order as the constructor's).
  void apply(std::vector<double>* row);
  /// Whether the columns hold joint angles (--noise-angle has something to do).
  bool hasAngleColumns() const { return !angle_.empty(); }
  /// Whether the columns hold accelerometer readings (--noise-acc).
  bool hasAccelerometerColumns() const { return !acc_.empty(); }
  /// The gyroscope biases drawn (one per B.wx, B.wy, B.wz column, in column order).
  const std::vector<double>& gyroBiases() const { return bias_; }

 private:
  NoiseOptions options_;
  std::vector<int> gyro_, angle_, quat_, acc_;  // quat_: index of each body's qw
  std::vector<double> bias_;
  std::mt19937_64 gen_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace app
}  // namespace lieflow
