/// \file
/// The mechanism spring fit's model (mechanism_spring_fit.hpp): the tree in
/// joint coordinates with the joint formulation's dynamics on any scalar
/// (dynamics/joint_space/scalar_dynamics.hpp), advanced by classical RK4 on
/// (q, q̇) — on ℝ²ⁿ RKMK4 is RK4 — in the scalar Ceres asks for.
#pragma once

#include <string>

#include "dynamics/joint_space/articulated_model.hpp"
#include "dynamics/joint_space/scalar_dynamics.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {

template <typename T>
using MechanismForces = articulated::CoordinateForces<T>;
template <typename T>
using MechanismDynamics = articulated::ScalarDynamics<T>;

/// Throws InvalidInput (field `field`) unless the model is a tree of
/// revolute and universal joints hanging from the ground (the fit's state is
/// the joint angles and their rates, read from the recording's angle or
/// gyroscope columns): no spherical joint (a rotation-only body no joint
/// reaches is on an implicit one), no slide, gimbal or weld, no prescribed
/// coordinate.
inline void requireMechanismSupported(const articulated::ArticulatedModel& model, const std::string& field) {
  for (int i = 0; i < model.bodyCount(); ++i) {
    const articulated::ArticulatedBody& b = model.bodies[static_cast<std::size_t>(i)];
    const std::string& name = model.names[static_cast<std::size_t>(i)];
    const bool hinges = b.kind == articulated::JointKind::kRevolute || b.kind == articulated::JointKind::kUniversal;
    if (!hinges || b.offset)
      throw InvalidInput(field, "body '" + name + "' " +
                                    (b.kind == articulated::JointKind::kSpherical && b.scene_joint < 0
                                         ? std::string("is not joined to the ground (a free body turns on no joint "
                                                       "of the scene)")
                                         : std::string("hangs on a joint that is not a revolute or a universal one")) +
                                    ": the mechanism spring fit takes trees of revolute and universal joints "
                                    "hanging from the ground");
    for (int k = 0; k < b.coordinates(); ++k)
      if (b.prescribed(k))
        throw InvalidInput(field, "the joint of body '" + name + "' has prescribed motion: nothing to fit there");
  }
}

/// One classical RK4 step of (q, q̇) from t to t + h.
template <typename T>
void rk4Step(const MechanismDynamics<T>& dynamics, const MechanismForces<T>& forces, double t, double h,
             typename MechanismDynamics<T>::Vec* q, typename MechanismDynamics<T>::Vec* v) {
  using Vec = typename MechanismDynamics<T>::Vec;
  const Vec a1 = dynamics.accelerations(t, *q, *v, forces);
  const Vec q2 = *q + (0.5 * h) * *v, v2 = *v + (0.5 * h) * a1;
  const Vec a2 = dynamics.accelerations(t + 0.5 * h, q2, v2, forces);
  const Vec q3 = *q + (0.5 * h) * v2, v3 = *v + (0.5 * h) * a2;
  const Vec a3 = dynamics.accelerations(t + 0.5 * h, q3, v3, forces);
  const Vec q4 = *q + h * v3, v4 = *v + h * a3;
  const Vec a4 = dynamics.accelerations(t + h, q4, v4, forces);
  *q += (h / 6.0) * (*v + 2.0 * v2 + 2.0 * v3 + v4);
  *v += (h / 6.0) * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
}

}  // namespace calibration
}  // namespace lieflow
