/// \file
/// Synthetic measurement noise on trajectory rows, so that `lieflow simulate`
/// writes recordings for `lieflow calibrate` (README "Recordings"):
///   --noise-gyro σ   (rad/s)  every B.wx, B.wy, B.wz + N(0, σ²), independently;
///   --noise-angle σ  (rad)    every joint angle J.phi, J.phi1, J.phi2 + N(0, σ²);
///   --noise-quat σ   (rad)    every body quaternion q ← q ⊗ exp(δ), δ ~ N(0, σ² I₃)
///                             a body-frame rotation (the angle error has RMS √3 σ),
///                             written with q_w ≥ 0;
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
  unsigned long long seed = 1;
  bool any() const { return gyro > 0.0 || angle > 0.0 || quaternion > 0.0; }
};

class RecordingNoise {
 public:
  RecordingNoise(const std::vector<std::string>& columns, const NoiseOptions& options);
  /// Adds the noise to one row (same column order as the constructor's).
  void apply(std::vector<double>* row);
  /// Whether the columns hold joint angles (--noise-angle has something to do).
  bool hasAngleColumns() const { return !angle_.empty(); }

 private:
  NoiseOptions options_;
  std::vector<int> gyro_, angle_, quat_;  // quat_: index of each body's qw
  std::mt19937_64 gen_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace app
}  // namespace lieflow
