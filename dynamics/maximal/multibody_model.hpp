/// \file
/// A multibody system in maximal coordinates: rigid bodies, each with its own
/// pose (R, p) and velocity (v world, ω body) as in dynamics/constraints/, joined
/// by joints that are constraint objects of dynamics/constraints/ imposed with
/// Lagrange multipliers.
///
/// Per body the tangent (and acceleration) ordering is (v, ω), matching the
/// (δp, δθ) columns of the constraint blocks. A rotation-only body has no
/// translational coordinates (its centre of mass p is held fixed by an
/// external support, gravity on it is carried by that support): it has 3
/// coordinates ω and only the δθ columns of its blocks are used.
///
/// Newton–Euler per body (README "Conventions"):
///   m v̇ = m g + f                (world frame),
///   J ω̇ + ω × J ω = τ            (body frame, J about the CoM in body axes).
#pragma once

#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "dynamics/constraints/constraints.hpp"
#include "dynamics/joint_types.hpp"
#include "dynamics/maximal/schur_solver.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace multibody {

using constraints::BodyPose;
using constraints::BodyVelocity;

struct RigidBody {
  std::string name;
  double mass = 1.0;                                       ///< m > 0 (ignored if rotation_only)
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();   ///< about the CoM, body axes, SPD
  bool rotation_only = false;                              ///< no translational coordinates
  int dofs() const { return rotation_only ? 3 : 6; }
};

/// A joint between bodies `main` and `secondary` (body indices, kGround = −1
/// for the world). The constraint's "main"/"secondary" slots are these bodies.
struct Joint {
  std::string name;
  int main = kGround;
  int secondary = kGround;
  JointConstraint constraint;
  /// How messages name the joint (e.g. "scene.json: joints[3] (hinge)");
  /// default "joints[k] (name)".
  std::string label = {};
};

/// External load on a body: force f (world, through the CoM) and moment τ
/// (body frame, about the CoM).
struct BodyLoad {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
};

/// State of all bodies (indexed like MultibodyModel::bodies).
struct MultibodyState {
  std::vector<BodyPose<double>> poses;
  std::vector<BodyVelocity<double>> velocities;
};

struct MultibodyModel {
  std::vector<RigidBody> bodies;
  std::vector<Joint> joints;
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);

  /// Adds a body and returns its index. Checks (InvalidInput, fields
  /// "bodies[i].mass" / "bodies[i].inertia"): mass finite > 0 (unless
  /// rotation-only), inertia finite, symmetric (1e-9 relative) and positive
  /// definite.
  int addBody(const RigidBody& body) {
    const int i = static_cast<int>(bodies.size());
    checkBody(body, i);
    bodies.push_back(body);
    return i;
  }

  /// Adds a joint and returns its index. Checks (fields "joints[k].main",
  /// "joints[k].secondary"): indices are kGround or existing bodies, and the
  /// two are different.
  int addJoint(const Joint& joint) {
    const int k = static_cast<int>(joints.size());
    checkJoint(joint, k);
    joints.push_back(joint);
    return k;
  }

  /// Σ dofs over bodies.
  int dofs() const {
    int n = 0;
    for (const auto& b : bodies) n += b.dofs();
    return n;
  }
  /// Σ rows over joints.
  int constraintCount() const {
    int m = 0;
    for (const auto& j : joints) m += constraintRows(j.constraint);
    return m;
  }

  /// "joints[k] (name)": how messages refer to joint k.
  std::string jointLabel(int k) const {
    if (k >= 0 && k < static_cast<int>(joints.size()) && !joints[k].label.empty()) return joints[k].label;
    std::ostringstream s;
    s << "joints[" << k << "]";
    if (k >= 0 && k < static_cast<int>(joints.size()) && !joints[k].name.empty())
      s << " (" << joints[k].name << ")";
    return s.str();
  }

  /// Re-checks every body and joint and that `state` has one pose and one
  /// velocity per body, all finite.
  void validate(const MultibodyState& state) const {
    validateModel();
    validateState(state);
  }

  /// Only the model part of validate(): every body and joint.
  void validateModel() const {
    for (std::size_t i = 0; i < bodies.size(); ++i) checkBody(bodies[i], static_cast<int>(i));
    for (std::size_t k = 0; k < joints.size(); ++k) checkJoint(joints[k], static_cast<int>(k));
  }

  /// Re-checks body i (as addBody does).
  void validateBody(int i) const { checkBody(bodies[i], i); }

  /// Only the state part of validate(): one pose and one velocity per body,
  /// all finite.
  void validateState(const MultibodyState& state) const {
    if (state.poses.size() != bodies.size() || state.velocities.size() != bodies.size()) {
      std::ostringstream r;
      r << "state has " << state.poses.size() << " poses and " << state.velocities.size()
        << " velocities for " << bodies.size() << " bodies";
      throw InvalidInput("state", r.str());
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const auto& P = state.poses[i];
      const auto& V = state.velocities[i];
      if (!P.p.allFinite() || !P.R.matrix().allFinite() || !V.v.allFinite() ||
          !V.omega.allFinite())
        throw InvalidInput("state.bodies[" + std::to_string(i) + "]", "non-finite pose or velocity");
    }
  }

 private:
  static void checkBody(const RigidBody& b, int i) {
    const std::string f = "bodies[" + std::to_string(i) + "]";
    if (!b.rotation_only && !(std::isfinite(b.mass) && b.mass > 0.0))
      throw InvalidInput(f + ".mass", "must be finite and > 0");
    if (!b.inertia.allFinite()) throw InvalidInput(f + ".inertia", "must be finite");
    const double scale = b.inertia.norm();
    if (!((b.inertia - b.inertia.transpose()).norm() <= 1e-9 * scale))
      throw InvalidInput(f + ".inertia", "must be symmetric");
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(b.inertia, Eigen::EigenvaluesOnly);
    if (!(es.eigenvalues().minCoeff() > 1e-12 * scale) || !(scale > 0.0))
      throw InvalidInput(f + ".inertia", "must be positive definite");
  }

  void checkJoint(const Joint& j, int k) const {
    const std::string f = "joints[" + std::to_string(k) + "]";
    const int n = static_cast<int>(bodies.size());
    if (j.main < kGround || j.main >= n)
      throw InvalidInput(f + ".main", "unknown body index " + std::to_string(j.main));
    if (j.secondary < kGround || j.secondary >= n)
      throw InvalidInput(f + ".secondary", "unknown body index " + std::to_string(j.secondary));
    if (j.main == j.secondary)
      throw InvalidInput(f + ".secondary", j.main == kGround ? "joint between ground and ground"
                                                            : "joint between a body and itself");
  }
};

}  // namespace multibody
}  // namespace lieflow
