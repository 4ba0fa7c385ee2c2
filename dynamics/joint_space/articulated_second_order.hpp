/// \file
/// A tree in joint coordinates for the generalized-α method
/// (integrators/generalized_alpha.hpp): the geometry of ArticulatedState
/// (q ⊕ δq adds on the angles and multiplies each spherical joint's N by
/// exp(δθ) on the right; T(δq) is I on the angles and Jr(δθ) on the
/// rotations) and M(q) v̇ + g(q, v, t) = 0 from ArticulatedSystem.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "integrators/second_order_traits.hpp"
#include "dynamics/joint_space/articulated_system.hpp"

namespace lieflow {

template <>
struct SecondOrderStateTraits<articulated::ArticulatedState> {
  using Scalar = double;
  using State = articulated::ArticulatedState;
  static constexpr int kDof = Eigen::Dynamic;
  using Vector = Eigen::VectorXd;
  using Matrix = Eigen::MatrixXd;

  static int dofs(const State& y) { return y.dofs(); }
  static const Vector& velocity(const State& y) { return y.u; }
  static void advanceInto(const State& y, const Vector& dq, const Vector& v, State* out) {
    const int nq = y.scalarCount();
    out->q = y.q + dq.head(nq);
    out->N.resize(y.N.size());
    for (std::size_t k = 0; k < y.N.size(); ++k)
      out->N[k] = y.N[k] * SO3d::exp(dq.segment<3>(nq + 3 * static_cast<int>(k)));
    out->u = v;
  }
  static void tangentOperatorInto(const State& y, const Vector& dq, Matrix* T) {
    T->setIdentity(dq.size(), dq.size());
    const int nq = y.scalarCount();
    for (std::size_t k = 0; k < y.N.size(); ++k) {
      const int o = nq + 3 * static_cast<int>(k);
      T->block<3, 3>(o, o) = SO3d::Jr(dq.segment<3>(o));
    }
  }
  static bool identical(const State& a, const State& b) {
    return a.u.size() == b.u.size() && a.u == b.u && articulated::ArticulatedSystem::sameConfiguration(a, b);
  }
};

template <>
struct SecondOrderSystemTraits<articulated::ArticulatedSystem> {
  using Scalar = double;
  using State = articulated::ArticulatedState;
  using Vector = Eigen::VectorXd;
  using Matrix = Eigen::MatrixXd;
  static void evaluate(const articulated::ArticulatedSystem& s, double t, const State& y, Matrix* M, Vector* g,
                       Matrix* Ct, Matrix* Kt) {
    s.secondOrderTerms(t, y, M, g, Ct, Kt);
  }
  static const std::vector<std::vector<int>>& independentBlocks(const articulated::ArticulatedSystem& s) {
    return s.independentBlocks();
  }
};

}  // namespace lieflow
