/// \file
/// The joint formulation's dynamics in any scalar (double or ceres::Jet) for
/// the calibration fits, which differentiate the discrete flow through it:
/// forward dynamics by Newton–Euler columns (small trees) or the
/// articulated-body algorithm, inverse dynamics by the recursive
/// Newton–Euler algorithm, the mass matrix by its columns — all on the
/// tree passes the simulator runs (tree_passes.hpp: one
/// implementation of each joint type's kinematics and of the algorithms,
/// T = double in ArticulatedSystem, T = Jet here). What this class adds:
/// a joint's axis as a parameter (setAxis), the spherical joints'
/// rotations as inputs (the part of the configuration q leaves out), the
/// springs, dashpots and rest positions as parameters (CoordinateForces, in
/// place of the scene's drives), and for one body on a revolute joint to
/// the ground a closed form (GroundedHinge) read off the general passes.
/// tests/dynamics/scalar_dynamics_test.cpp checks it against the simulator
/// to 1e-11.
///
/// Joints: revolute, universal, gimbal, prismatic, spherical and welds, on
/// either side of their joint (the parent main or secondary), rotation-only
/// bodies. Not here: free roots, offset universal joints, gimbals hanging
/// from their secondary body and prescribed coordinates
/// (requireScalarDynamics says so; a fit has nothing to fit there).
///
/// The motion satisfies τ(q, q̇, q̈) = Q with Q_k = −k_k (q_k − q₀ₖ) − c_k q̇_k
/// + M_k(t) (springs, dashpots and applied moments, on the coordinates that
/// have them); τ is the inverse dynamics, M's columns τ(q, 0, e_j) without
/// velocity products and gravity.
#pragma once

#include <array>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "dynamics/joint_space/articulated_model.hpp"
#include "dynamics/joint_space/grounded_hinge.hpp"
#include "dynamics/joint_space/tree_passes.hpp"
#include "liegroup/flatten.hpp"
#include "liegroup/invalid_input.hpp"

// The methods that run the tree passes are LIEFLOW_NOT_FLATTENED
// (liegroup/flatten.hpp): the fits flatten their residuals, and GCC 12 failed
// (an internal compiler error in loop unrolling, cunrolli) when the tree
// passes on Jets were flattened into them. The boundary costs nothing
// measurable (on the hand-written passes before: bench_spring_fit's
// universal fit 244–250 ms without it, 237–255 ms with it).

namespace lieflow {
namespace articulated {

/// Spring, dashpot and rest position of every joint coordinate (size nq
/// each, by the model's q index), in the scalar of the evaluation.
template <typename T>
struct CoordinateForces {
  std::vector<T> stiffness, damping, rest_angle;
};

/// The model's own springs, dashpots and rest positions (its drives).
template <typename T>
CoordinateForces<T> modelForces(const ArticulatedModel& model) {
  CoordinateForces<T> f;
  f.stiffness.assign(model.scalar_coordinates, T(0.0));
  f.damping = f.rest_angle = f.stiffness;
  for (int i = 0; i < model.bodyCount(); ++i)
    for (int k = 0; k < model.bodies[i].coordinates(); ++k) {
      const CoordinateDrive& d = model.drives[i][k];
      const int j = model.bodies[i].q_begin + k;
      f.stiffness[j] = T(d.stiffness);
      f.damping[j] = T(d.damping);
      f.rest_angle[j] = T(d.rest_angle);
    }
  return f;
}

/// Throws InvalidInput (field `field`) unless ScalarDynamics models the
/// tree: no free root, no offset universal joint, no prescribed coordinate.
inline void requireScalarDynamics(const ArticulatedModel& model, const std::string& field) {
  for (int i = 0; i < model.bodyCount(); ++i) {
    const ArticulatedBody& b = model.bodies[i];
    const std::string& name = model.names[i];
    if (b.kind == JointKind::kFree)
      throw InvalidInput(field, "body '" + name + "' is a free root (no joint of the scene reaches it from the "
                                "ground): the joint-coordinate dynamics on any scalar takes trees hanging from the ground");
    if (b.offset)
      throw InvalidInput(field, "body '" + name + "' hangs on an offset universal joint, which the joint-coordinate "
                                "dynamics on any scalar does not take");
    if (b.kind == JointKind::kGimbal && !b.parent_is_main)
      throw InvalidInput(field, "body '" + name + "' is the main body of its gimbal: the joint-coordinate dynamics "
                                "on any scalar takes gimbals hanging from their main body");
    for (int k = 0; k < b.coordinates(); ++k)
      if (b.prescribed(k))
        throw InvalidInput(field, "the joint of body '" + name + "' has prescribed motion: nothing to fit there");
  }
}

template <typename T>
class ScalarDynamics {
 public:
  using Vec = Eigen::Matrix<T, Eigen::Dynamic, 1>;
  using Vec3 = Eigen::Matrix<T, 3, 1>;
  using Vec6 = Eigen::Matrix<T, 6, 1>;
  using Mat3 = Eigen::Matrix<T, 3, 3>;
  using Mat = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

  /// The model must outlive the dynamics. Throws as requireScalarDynamics.
  explicit ScalarDynamics(const ArticulatedModel& model, const std::string& field = "`scene`")
      : ScalarDynamics(model, field, false) {
    if (isGroundedHinge(model)) hinge_ = hingeConstants(ScalarDynamics<double>(model, field, false));
  }

  /// Replaces body i's joint's first axis (a revolute joint's axis a, unit —
  /// a fit keeps it on the sphere — in the joint's main body's frame): the
  /// axis as a parameter of a fit.
  /// (The closed form of a grounded hinge rests on the model's axis: off.)
  void setAxis(int body, const Vec3& axis) {
    JointFrame<T>& frame = frames_[static_cast<std::size_t>(body)];
    if constexpr (std::is_same<T, double>::value)
      frame = jointFrame<double>(axis, m_.bodies[static_cast<std::size_t>(body)].R_ref);
    frame.axis1 = axis;
    frame.parameter = true;
    hinge_.valid = false;
  }

  /// The spherical joints' relative rotations N (by the model's rotation
  /// index; identity until set): the part of the configuration q leaves out.
  void setRotations(const std::vector<Mat3>& rotations) { N_rel_ = rotations; }
  /// The same for spherical joint k alone.
  void setRotation(int k, const Mat3& rotation) { N_rel_[static_cast<std::size_t>(k)] = rotation; }

  int coordinates() const { return m_.scalar_coordinates; }
  int dofs() const { return m_.dofs(); }
  /// Whether accelerations() takes GroundedHinge's closed form.
  bool closedForm() const { return hinge_.valid; }
  /// Its constants (valid: false when the model is not a grounded hinge).
  const GroundedHinge& groundedHinge() const { return hinge_; }

  /// Q: the springs', dashpots' and applied moments' generalized forces.
  Vec appliedForces(double t, const Vec& q, const Vec& u, const CoordinateForces<T>& forces) const {
    Vec Q = Vec::Zero(dofs());
    const FitLoads loads{m_, forces};
    for (int i = 0; i < m_.bodyCount(); ++i) {
      const ArticulatedBody& b = m_.bodies[static_cast<std::size_t>(i)];
      for (int k = 0; k < b.coordinates(); ++k)
        Q[b.u_begin + k] = loads.coordinate(i, k, t, q[b.q_begin + k], u[b.u_begin + k]);
    }
    return Q;
  }

  /// q̈ (u̇) at (t, q, u) under `forces` and the model's applied moments:
  /// the grounded hinge's closed form; else, up to kNewtonEulerMaxDofs
  /// degrees of freedom, newtonEulerAccelerations; beyond,
  /// articulatedBodyAccelerations (the crossover measured in ceres::Jet,
  /// bench/calibration/bench_scalar_dynamics.cpp).
  Vec accelerations(double t, const Vec& q, const Vec& u, const CoordinateForces<T>& forces) const {
    if (hinge_.valid) {
      Vec out(1);
      out[0] = groundedHingeAcceleration(hinge_, q[0], u[0], forces.stiffness[0], forces.damping[0],
                                         forces.rest_angle[0], m_.drives[0][0].appliedMoment(t));
      return out;
    }
    return dofs() <= kNewtonEulerMaxDofs ? newtonEulerAccelerations(t, q, u, forces)
                                         : articulatedBodyAccelerations(t, q, u, forces);
  }

  /// u̇ = M⁻¹ (Q − h) with h = τ(q, u, 0) and M's columns the
  /// acceleration-only Newton–Euler passes, all on one kinematics pass:
  /// n + 1 passes with the bodies' compact inertias (no 6 × 6 products),
  /// O(n²) and an n × n solve.
  LIEFLOW_NOT_FLATTENED Vec newtonEulerAccelerations(double t, const Vec& q, const Vec& u,
                                                     const CoordinateForces<T>& forces) const {
    const int n = dofs();
    const TreePasses<T> passes = passesOn(false);
    passes.forwardPass(t, StateView{q, u, N_rel_}, true, true, NoLoads{});
    Vec h, column;
    passes.biasForces(&h);
    Mat M(n, n);
    for (int j = 0; j < n; ++j) {
      passes.massMatrixColumn(j, &column);
      M.col(j) = column;
    }
    return M.ldlt().solve(appliedForces(t, q, u, forces) - h);
  }

  /// u̇ by the articulated-body algorithm on the same passes (the
  /// simulator's, O(n), with 6 × 6 articulated inertias).
  LIEFLOW_NOT_FLATTENED Vec articulatedBodyAccelerations(double t, const Vec& q, const Vec& u,
                                                         const CoordinateForces<T>& forces) const {
    const TreePasses<T> passes = passesOn(true);
    passes.forwardPass(t, StateView{q, u, N_rel_}, true, true, FitLoads{m_, forces});
    Vec udot(dofs());
    passes.solve(Vec6::Zero(), &udot);
    return udot;
  }

  /// M(q): column j the inverse dynamics of u̇ = e_j without velocity terms.
  LIEFLOW_NOT_FLATTENED Mat massMatrix(const Vec& q) const {
    const int n = dofs();
    const Vec zero = Vec::Zero(n);
    const TreePasses<T> passes = passesOn();
    passes.forwardPass(0.0, StateView{q, zero, N_rel_}, true, false, NoLoads{});
    Mat M(n, n);
    Vec column;
    for (int j = 0; j < n; ++j) {
      passes.massMatrixColumn(j, &column);
      M.col(j) = column;
    }
    return M;
  }

  /// ½ uᵀ M(q) u − Σ m_i g · c_i + Σ ½ k_j (q_j − q₀ⱼ)² (the weight of a
  /// rotation-only body is its support's): conserved without dashpots and
  /// applied moments.
  T energy(const Vec& q, const Vec& u, const CoordinateForces<T>& forces) const {
    T e = T(0.5) * u.dot(massMatrix(q) * u);  // (the bodies' centres are q's now)
    const Vec3 g = m_.gravity.template cast<T>();
    for (int i = 0; i < m_.bodyCount(); ++i) {
      const ArticulatedBody& b = m_.bodies[static_cast<std::size_t>(i)];
      if (!b.rotation_only) e -= T(b.mass) * g.dot(bodies_[static_cast<std::size_t>(i)].c);
    }
    for (int j = 0; j < coordinates(); ++j) {
      const T d = q[j] - forces.rest_angle[j];
      e += T(0.5) * forces.stiffness[j] * d * d;
    }
    return e;
  }

  /// Each body's angular velocity in its own axes (what its gyroscope reads).
  LIEFLOW_NOT_FLATTENED std::vector<Vec3> bodyRates(const Vec& q, const Vec& u) const {
    passesOn().forwardPass(0.0, StateView{q, u, N_rel_}, false, true, NoLoads{});
    std::vector<Vec3> out(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i)
      out[i] = bodies_[i].R.transpose() * bodies_[i].V.template head<3>();
    return out;
  }

  /// τ(q, u, u̇): the generalized forces the joints transmit (the recursive
  /// Newton–Euler algorithm; τ = Q on the motion).
  LIEFLOW_NOT_FLATTENED Vec inverseDynamics(const Vec& q, const Vec& u, const Vec& udot) const {
    const TreePasses<T> passes = passesOn();
    passes.forwardPass(0.0, StateView{q, u, N_rel_}, true, true, NoLoads{});
    Vec tau;
    passes.inverseDynamics(udot, &tau);
    return tau;
  }

 private:
  template <typename>
  friend class ScalarDynamics;

  /// The passes' view of (q, u) and the spherical joints' rotations.
  struct StateView {
    const Vec& q;
    const Vec& u;
    const std::vector<Mat3>& N;
  };
  /// The fit's loads: its springs, dashpots and rest positions on every
  /// coordinate, with the model's applied moments M(t).
  struct FitLoads {
    const ArticulatedModel& model;
    const CoordinateForces<T>& forces;
    bool acts(const ArticulatedBody&, int) const { return true; }
    T coordinate(int i, int k, double t, const T& phi, const T& phidot) const {
      const std::size_t j = static_cast<std::size_t>(model.bodies[static_cast<std::size_t>(i)].q_begin + k);
      return -forces.stiffness[j] * (phi - forces.rest_angle[j]) - forces.damping[j] * phidot +
             T(model.drives[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)].appliedMoment(t));
    }
    template <class Body, class V3>
    void external(int, double, Body*, const V3&, const V3&) const {}
  };
  /// None: what inverse dynamics, the mass matrix and the rates need.
  struct NoLoads {
    bool acts(const ArticulatedBody&, int) const { return false; }
    T coordinate(int, int, double, const T&, const T&) const { return T(0.0); }
    template <class Body, class V3>
    void external(int, double, Body*, const V3&, const V3&) const {}
  };

  ScalarDynamics(const ArticulatedModel& model, const std::string& field, bool /*general only*/)
      : m_(model), frames_(modelFrames<T>(model)), bodies_(model.bodies.size()) {
    requireScalarDynamics(model, field);
    N_rel_.assign(static_cast<std::size_t>(model.rotations), Mat3::Identity());
  }

  /// The passes on this model, frames and workspace; `articulated`: with
  /// the articulated-body algorithm's 6 × 6 inertias.
  TreePasses<T> passesOn(bool articulated = false) const {
    return TreePasses<T>(m_, frames_, bodies_, no_roots_, false, articulated);
  }

  /// GroundedHinge's constants from the general algorithm (in double).
  static GroundedHinge hingeConstants(const ScalarDynamics<double>& general) {
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1), one = Eigen::VectorXd::Ones(1);
    auto gravity = [&](double q) { return -general.inverseDynamics(Eigen::VectorXd::Constant(1, q), zero, zero)[0]; };
    const double g0 = gravity(0.0), g90 = gravity(0.5 * kPi), g180 = gravity(kPi);
    GroundedHinge h;
    h.gravity_const = 0.5 * (g0 + g180);
    h.gravity_cos = 0.5 * (g0 - g180);
    h.gravity_sin = g90 - h.gravity_const;
    h.inertia = general.inverseDynamics(zero, zero, one)[0] + g0;
    h.valid = h.inertia > 0.0;
    return h;
  }
  static constexpr double kPi = 3.14159265358979323846;
  /// Most degrees of freedom for which accelerations() takes the Newton–Euler
  /// columns rather than the articulated-body algorithm.
  /// bench_scalar_dynamics (chains of revolute joints, ceres::Jet<double, 8>):
  /// the columns take 0.82, 0.86, 0.92 of the algorithm's time at n = 2, 3, 4,
  /// 1.05 at 5 and 1.58 at 10.
  static constexpr int kNewtonEulerMaxDofs = 4;

  const ArticulatedModel& m_;
  std::vector<JointFrame<T>> frames_;
  mutable std::vector<TreeBody<T>> bodies_;  ///< the passes' workspace
  typename TreePasses<T>::RootMomenta no_roots_;  ///< (no free roots here)
  std::vector<Mat3> N_rel_;
  GroundedHinge hinge_;
};

}  // namespace articulated
}  // namespace lieflow
