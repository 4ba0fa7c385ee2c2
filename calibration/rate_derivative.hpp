/// \file
/// The derivative of a recorded vector signal (a gyroscope's rates) at one
/// sample, from the samples around it.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace lieflow {
namespace calibration {

/// Half window of rateDerivative: samples k − kRateWindow … k + kRateWindow.
constexpr int kRateWindow = 6;

/// dω/dt at sample k (kRateWindow ≤ k < n − kRateWindow): the slope at t_k of
/// the cubic that fits ω over the window in least squares (Savitzky–Golay,
/// any spacing). A central difference would add noise σ_ω/(√2 Δt); this
/// window divides that noise by ~4 (‖c‖ = 0.18/Δt against 0.71/Δt), and the
/// cubic keeps the smoothing error at O((mΔt)⁴ ω⁽⁵⁾) where a local line or
/// quadratic leaves O((mΔt)² ω⃛). On uniform samples the weights are odd about
/// k (the centre sample's weight is 0), so the slope's noise is uncorrelated
/// with the noise of ω_k itself.
Eigen::Vector3d rateDerivative(const std::vector<double>& t, const std::vector<Eigen::Vector3d>& w, std::size_t k);

}  // namespace calibration
}  // namespace lieflow
