/// \file
/// The mechanism spring fit's model (mechanism_spring_fit.hpp): the tree in
/// joint coordinates with the joint formulation's dynamics on any scalar
/// (dynamics/joint_space/scalar_dynamics.hpp), its state (q, N, u) — joint
/// angles, the spherical joints' relative rotations, rates — advanced by
/// lieflow's RKMK stepper with the classical RK4 tableau (integrators/rkmk.hpp;
/// on the angles and rates that is RK4) in the scalar Ceres asks for.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "dynamics/joint_space/articulated_model.hpp"
#include "dynamics/joint_space/articulated_state.hpp"
#include "dynamics/joint_space/scalar_dynamics.hpp"
#include "integrators/butcher_tableau.hpp"
#include "integrators/rkmk.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/scalar.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace calibration {

template <typename T>
using MechanismForces = articulated::CoordinateForces<T>;
template <typename T>
using MechanismDynamics = articulated::ScalarDynamics<T>;

/// Throws InvalidInput (field `field`) unless the model is a tree of
/// revolute, universal and spherical joints hanging from the ground (a
/// rotation-only body no joint reaches turns on an implicit spherical one):
/// no slide, gimbal, weld or offset universal joint, no prescribed
/// coordinate. The fit's state is the joint angles, the spherical joints'
/// rotations and the rates, read from the recording's angle or gyroscope
/// columns.
inline void requireMechanismSupported(const articulated::ArticulatedModel& model, const std::string& field) {
  for (int i = 0; i < model.bodyCount(); ++i) {
    const articulated::ArticulatedBody& b = model.bodies[static_cast<std::size_t>(i)];
    const std::string& name = model.names[static_cast<std::size_t>(i)];
    const bool supported = b.kind == articulated::JointKind::kRevolute ||
                           b.kind == articulated::JointKind::kUniversal ||
                           b.kind == articulated::JointKind::kSpherical;
    if (!supported || b.offset)
      throw InvalidInput(field, "body '" + name +
                                    "' hangs on a joint that is not a revolute, universal or spherical one: the "
                                    "mechanism spring fit takes trees of those joints hanging from the ground");
    for (int k = 0; k < b.coordinates(); ++k)
      if (b.prescribed(k))
        throw InvalidInput(field, "the joint of body '" + name + "' has prescribed motion: nothing to fit there");
  }
}

/// The tree's state in the scalar of the fit: q (the nq joint angles), N
/// (the spherical joints' relative rotations) and u (nq angle rates, then 3
/// body-axis rates per spherical joint): the simulator's state type on T.
template <typename T>
using MechanismState = articulated::ArticulatedStateT<T>;

/// The tree as a system for integrators/' steppers: f(t, y) = (u, u̇), the
/// rotations turning at their joints' body-axis rates (Ṅ = N ω̂).
template <typename T>
class MechanismFlow {
 public:
  using Scalar = T;
  using State = MechanismState<T>;
  using Tangent = typename State::Tangent;

  /// The dynamics (whose rotations the flow sets) and the forces must
  /// outlive the flow.
  MechanismFlow(MechanismDynamics<T>* dynamics, const MechanismForces<T>& forces)
      : dynamics_(dynamics), forces_(forces) {}

  void velocity(const T& t, const State& y, Tangent* f) const {
    const int n = static_cast<int>(y.u.size());
    for (std::size_t k = 0; k < y.N.size(); ++k) dynamics_->setRotation(static_cast<int>(k), y.N[k].matrix());
    f->resize(2 * n);
    f->head(n) = y.u;
    f->tail(n) = dynamics_->accelerations(scalarValue(t), y.q, y.u, forces_);
  }

 private:
  MechanismDynamics<T>* dynamics_;
  const MechanismForces<T>& forces_;
};

/// RKMK with the classical RK4 tableau: fourth order on the rotations too.
template <typename T>
RkmkStepper<MechanismState<T>> mechanismStepper() {
  return RkmkStepper<MechanismState<T>>(ButcherTableau::rk4());
}

/// The turns of spherical subtrees that body-axis rates (gyroscopes) cannot
/// see: per spherical joint to the ground, 1 (about the vertical through it)
/// when weight acts on its subtree, else 3 — the null space of a fit to them.
inline int unobservableTurns(const articulated::ArticulatedModel& model) {
  int count = 0;
  for (int i = 0; i < model.bodyCount(); ++i) {
    const articulated::ArticulatedBody& b = model.bodies[static_cast<std::size_t>(i)];
    if (b.kind != articulated::JointKind::kSpherical || b.parent != articulated::kGround) continue;
    bool weighted = false;
    for (int j = i; j < model.bodyCount(); ++j) {  // the subtree: i and the bodies below it (tree order)
      int a = j;
      while (a != articulated::kGround && a != i) a = model.bodies[static_cast<std::size_t>(a)].parent;
      const articulated::ArticulatedBody& d = model.bodies[static_cast<std::size_t>(j)];
      if (a == i && !d.rotation_only && d.mass > 0.0) weighted = true;
    }
    count += weighted && model.gravity.squaredNorm() > 0.0 ? 1 : 3;
  }
  return count;
}

}  // namespace calibration
}  // namespace lieflow
