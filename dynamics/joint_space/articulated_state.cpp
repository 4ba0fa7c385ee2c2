// The state of a tree in joint coordinates, instantiated in double once.
#include "dynamics/joint_space/articulated_state.hpp"

#include "integrators/rigid_body_state.hpp"

namespace lieflow {
namespace articulated {

template struct ArticulatedStateT<double>;

bool isFinite(const ArticulatedState& y) {
  if (!y.q.allFinite() || !y.u.allFinite()) return false;
  for (const SO3d& R : y.N)
    if (!R.quaternion().coeffs().allFinite()) return false;
  return true;
}

}  // namespace articulated
}  // namespace lieflow
