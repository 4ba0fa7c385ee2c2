// The state of a tree in joint coordinates: ⊕, dexp⁻¹, the adaptive scale.
#include "dynamics/joint_space/articulated_state.hpp"

#include "integrators/rigid_body_state.hpp"

namespace lieflow {
namespace articulated {

void ArticulatedState::rplusInPlace(const Tangent& d) {
  const int nq = scalarCount(), n = dofs();
  q += d.head(nq);
  for (std::size_t k = 0; k < N.size(); ++k) N[k] *= SO3d::exp(d.segment<3>(nq + 3 * static_cast<int>(k)));
  u += d.tail(n);
}

void ArticulatedState::dexpInvRightInto(const Tangent& theta, const Tangent& v, int order, Tangent* out) const {
  *out = v;
  const int nq = scalarCount();
  for (std::size_t k = 0; k < N.size(); ++k) {
    const int o = nq + 3 * static_cast<int>(k);
    out->segment<3>(o) = detail::so3DexpInvRight<double>(theta.segment<3>(o), v.segment<3>(o), order);
  }
}

ArticulatedState::Tangent ArticulatedState::magnitude() const {
  const int n = dofs();
  Tangent m(2 * n);
  m.head(n).setOnes();
  m.tail(n) = u.cwiseAbs();
  return m;
}

bool isFinite(const ArticulatedState& y) {
  if (!y.q.allFinite() || !y.u.allFinite()) return false;
  for (const SO3d& R : y.N)
    if (!R.quaternion().coeffs().allFinite()) return false;
  return true;
}

}  // namespace articulated
}  // namespace lieflow
