/// \file
/// The state of a tree in joint coordinates: a point of
///   ℝ^nq × SO(3)^ns × ℝ^(nq + 3 ns)
/// (the revolute and universal angles, the spherical joints' relative
/// rotations N, the velocities u = [φ̇ (nq); ω_rel (3 ns)], ω_rel the child's
/// angular velocity relative to its parent in the child's frame, so that
/// Ṅ = N ω̂_rel).
///
/// Tangent (size 2 n, n = nq + 3 ns): [δφ (nq); δθ (3 ns); δu (n)]; ⊕ adds
/// on the vector parts and multiplies N by exp(δθ) on the right, so dexp⁻¹
/// is the identity except on the SO(3) blocks. The size is known at run
/// time; the in-place operations of integrators/state_workspace.hpp let a
/// stepper reuse its storage (no heap allocation per step).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "integrators/rigid_body_state.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace articulated {

/// In any scalar T (double for the simulator, ceres::Jet for the fits that
/// differentiate the flow: calibration/mechanism_flow.hpp).
template <typename T>
struct ArticulatedStateT {
  using Scalar = T;
  using Vec = Eigen::Matrix<T, Eigen::Dynamic, 1>;
  using Tangent = Vec;
  static constexpr int kTangentDim = Eigen::Dynamic;

  Vec q;                  ///< nq angles (unwrapped)
  std::vector<SO3<T>> N;  ///< ns relative rotations
  Vec u;                  ///< nq + 3 ns velocities

  int scalarCount() const { return static_cast<int>(q.size()); }
  int dofs() const { return static_cast<int>(u.size()); }

  int tangentSize() const { return 2 * dofs(); }
  Tangent zeroTangent() const { return Tangent::Zero(tangentSize()); }

  void rplusInPlace(const Tangent& d) {
    const int nq = scalarCount(), n = dofs();
    q += d.head(nq);
    for (std::size_t k = 0; k < N.size(); ++k)
      N[k] *= SO3<T>::exp(d.template segment<3>(nq + 3 * static_cast<int>(k)));
    u += d.tail(n);
  }
  ArticulatedStateT rplus(const Tangent& d) const {
    ArticulatedStateT out = *this;
    out.rplusInPlace(d);
    return out;
  }
  void dexpInvRightInto(const Tangent& theta, const Tangent& v, int order, Tangent* out) const {
    *out = v;
    const int nq = scalarCount();
    for (std::size_t k = 0; k < N.size(); ++k) {
      const int o = nq + 3 * static_cast<int>(k);
      out->template segment<3>(o) =
          detail::so3DexpInvRight<T>(theta.template segment<3>(o), v.template segment<3>(o), order);
    }
  }
  Tangent dexpInvRight(const Tangent& theta, const Tangent& v, int order) const {
    Tangent out;
    dexpInvRightInto(theta, v, order, &out);
    return out;
  }
  /// Per-component scale of the adaptive error norm: 1 for positions (angles
  /// and rotations are O(1)), |u| for velocities.
  Tangent magnitude() const {
    const int n = dofs();
    Tangent m(2 * n);
    m.head(n).setOnes();
    m.tail(n) = u.cwiseAbs();
    return m;
  }
};

using ArticulatedState = ArticulatedStateT<double>;
extern template struct ArticulatedStateT<double>;

bool isFinite(const ArticulatedState& y);

}  // namespace articulated
}  // namespace lieflow
