/// \file
/// The benchmark chain of bench_chain.cpp and bench_chain_mujoco.cpp, in one
/// place so that the lieflow and MuJoCo benchmarks time the same system:
/// joints/multibody/chain_builder.hpp's chain of N rods (hinge to hinge
/// 0.5 m, centre of mass 0.25 m from each hinge along body x, masses in
/// [0.5, 0.9] kg drawn with seed 42, the full inertia below for every rod),
/// hinge axes alternating z / y in the parent frame, the first hinge to ground
/// at the origin, gravity (0, 0, −9.81), stepped with h = 1e-3.
#pragma once

#include <Eigen/Core>

#include "joints/multibody/chain_builder.hpp"

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

/// The chain of joints/multibody/chain_builder.hpp, axes alternating z / y,
/// with chainRodInertia() (state: the builder's random joint angles and rates).
inline multibody::MultibodyModel revoluteChain(int n, unsigned seed, multibody::MultibodyState* state) {
  return multibody::randomRevoluteChain(n, true, chainRodInertia(), seed, state);
}

}  // namespace bench
}  // namespace lieflow
