/// \file
/// The joint formulation's tree dynamics on any scalar (double, or
/// ceres::Jet where a calibration fit differentiates through it): per joint
/// type the kinematics pass, then the articulated-body algorithm's two
/// other passes (forward dynamics) or the recursive Newton–Euler algorithm
/// (inverse dynamics; columns of the mass matrix). The equations and
/// conventions are articulated_system.hpp's (Featherstone's spatial vectors
/// in world axes about the world origin). One implementation serves both
/// users: ArticulatedSystem (the simulator, T = double, with its loops,
/// variational steps and observables around it) and ScalarDynamics (the
/// fits, T = Jet; scalar_dynamics.hpp).
///
/// Inverse dynamics on the same pass (Featherstone 2008, §5.3, in world
/// coordinates): a_i = a_p + S_i u̇_i + c_i (c_i the bias acceleration Ṡu and
/// the prescribed columns' terms of the pass; a rotation-only body takes
/// P a_p), f_i = I_i a_i + p_i (p_i the bias force with gravity and program
/// torques as external forces), children's forces added to their parent's
/// (Pᵀ f through a rotation-only child's support), τ_i = S_iᵀ f_i. Its
/// rigid inertias act in compact form, I (α, a_O) = (J_w α + c × f, f) with
/// f = m (a_O + α × c), and without the bias terms (c_i, p_i) a pass gives
/// M u̇: one kinematics pass serves h = τ(q, u, 0) and every column of M.
///
/// What stays out of the Jets' derivative arithmetic: the model's constants
/// (axes, Rodrigues bases, anchors on the ground, masses, gravity, ±1 signs)
/// are doubles, and a joint on the ground skips its parent's identity pose
/// and zero twist. That is what keeps the fits' Jet evaluations as fast as
/// the hand-written 3-vector Newton–Euler they replace (bench_spring_fit's
/// universal fit 242 ms against 243 ms), and the simulator's double passes
/// as fast as before (0.9–1.0 times per step, bench_multibody).
///
/// A pass is a view (TreePasses) on a model, its joint frames and a
/// workspace, built per call; `Loads` gives the generalized force of each
/// free coordinate and the program torques (ModelLoads: the scene's drives).
#pragma once

#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/StdVector>

#include "dynamics/joint_space/articulated_model.hpp"
#include "dynamics/joint_space/spatial_algebra.hpp"

namespace lieflow {
namespace articulated {

/// One body's kinematics and articulated-body quantities (the passes' workspace).
template <typename T>
struct TreeBody {
  using Vec3 = Eigen::Matrix<T, 3, 1>;
  using Vec6 = Eigen::Matrix<T, 6, 1>;
  using Mat3 = Eigen::Matrix<T, 3, 3>;
  Mat3 R;                   ///< world orientation
  Vec3 c, x;                ///< centre of mass, joint anchor (world)
  Vec3 x2;                  ///< an offset universal joint's second anchor (world)
  std::array<T, 3> phi{{T(0.0), T(0.0), T(0.0)}}, phidot{{T(0.0), T(0.0), T(0.0)}},
      phiddot{{T(0.0), T(0.0), T(0.0)}};
  std::array<Vec3, 3> axis;  ///< world joint axes (revolute, universal, gimbal)
  Vec6 V, bias, a, pA;
  Mat3 Jw;                  ///< inertia about the centre of mass, world axes
  Vec6 f;                   ///< inverse dynamics: the force the joint transmits
  Eigen::Matrix<T, 6, 6> IA;
  Eigen::Matrix<T, 6, 3> S;  ///< free columns (first `free` of them)
  int free = 0;
  std::array<int, 3> free_u{{0, 0, 0}};  ///< the free columns' u indices
  Eigen::Matrix<T, 6, 3> U;              ///< I_A S
  Mat3 Dinv;                             ///< (Sᵀ I_A S)⁻¹
  Vec3 tau;                              ///< free generalized forces, then u − Uᵀ(...)
};

/// A joint's first axis a and the Rodrigues basis of its relative rotation:
/// exp(φ a) R_ref = cos φ A + sin φ B + C with A = (I − a aᵀ) R_ref,
/// B = [a]× R_ref, C = a aᵀ R_ref, so that a revolute or universal joint's
/// rotation costs a sine, a cosine and 27 multiply-adds. The axis is the
/// model's, or a fit's parameter (ScalarDynamics::setAxis: `parameter`).
/// The basis is kept in double: where a Jet axis is the parameter, the
/// rotation is exp(φ a) R_ref from the axis itself, and the model's
/// constants otherwise stay out of the Jets' derivative arithmetic.
template <typename T>
struct JointFrame {
  Eigen::Matrix<T, 3, 1> axis1;
  Eigen::Matrix3d A, B, C;  ///< of axis1 where T is double, else of the model's axis
  bool parameter = false;   ///< axis1 is not the model's axis
};

/// The frame of a joint with unit axis `a` and rest rotation R_ref.
template <typename T>
JointFrame<T> jointFrame(const Eigen::Vector3d& a, const Eigen::Matrix3d& R_ref) {
  JointFrame<T> f;
  f.axis1 = a.template cast<T>();
  const Eigen::Matrix3d aa = a * a.transpose();
  f.A = (Eigen::Matrix3d::Identity() - aa) * R_ref;
  f.B = hat(a) * R_ref;
  f.C = aa * R_ref;
  return f;
}

/// Every body's frame from the model's axes.
template <typename T>
std::vector<JointFrame<T>> modelFrames(const ArticulatedModel& model) {
  std::vector<JointFrame<T>> frames;
  for (const ArticulatedBody& b : model.bodies) frames.push_back(jointFrame<T>(b.axis1, b.R_ref));
  return frames;
}

/// The relative rotation M (main → secondary) of a revolute or universal
/// joint from the cosines and sines of its angles (articulated_model.hpp):
/// exp(φ₁ a₁) R_ref [exp(φ₂ a₂)].
template <typename T>
EIGEN_ALWAYS_INLINE Eigen::Matrix<T, 3, 3> jointRotation(const ArticulatedBody& b, const JointFrame<T>& r,
                                                         const std::array<T, 3>& c, const std::array<T, 3>& s) {
  Eigen::Matrix<T, 3, 3> M;
  if (!std::is_same<T, double>::value && r.parameter)
    M = rotationAbout(r.axis1, c[0], s[0]) * b.R_ref;
  else
    M = c[0] * r.A + s[0] * r.B + r.C;
  if (b.kind == JointKind::kUniversal) M = M * rotationAbout(b.axis2, c[1], s[1]);
  return M;
}

/// A gimbal's relative rotation M = E₁E₂E₃ R_ref (E_k = exp(φ_k e_k)) and its
/// second and third axes turned by the hinges before them, E₁e₂ and E₁E₂e₃
/// (main frame), from the cosines and sines of its angles.
template <typename T>
struct GimbalAxes {
  Eigen::Matrix<T, 3, 3> M;
  Eigen::Matrix<T, 3, 1> a2, a3;
};
template <typename T>
GimbalAxes<T> gimbalAxes(const ArticulatedBody& b, const std::array<T, 3>& c, const std::array<T, 3>& s) {
  using Mat3 = Eigen::Matrix<T, 3, 3>;
  const Mat3 E1 = rotationAbout(b.axis1, c[0], s[0]);
  const Mat3 E12 = E1 * rotationAbout(b.axis2, c[1], s[1]);
  return {Mat3(E12 * rotationAbout(b.axis3, c[2], s[2]) * b.R_ref), E1 * b.axis2, E12 * b.axis3};
}

/// An offset universal joint's secondary anchor x₂ = x + R_main exp(φ₁a₁) δ
/// (δ = offset_ref), which the first hinge carries.
template <typename T>
Eigen::Matrix<T, 3, 1> offsetAnchor(const ArticulatedBody& b, const Eigen::Matrix<T, 3, 1>& x,
                                    const Eigen::Matrix<T, 3, 3>& R_main, const T& c0, const T& s0) {
  return x + R_main * (rotationAbout(b.axis1, c0, s0) * b.offset_ref);
}

/// The scene's own loads: each coordinate's drive (spring, dashpot, applied
/// and program moments) where it has one, no program torque.
struct ModelLoads {
  const ArticulatedModel& model;
  bool acts(const ArticulatedBody& b, int k) const { return b.has_force[k]; }
  double coordinate(int i, int k, double t, double phi, double phidot) const {
    return model.drives[i][k].momentAt(t, phi, phidot);
  }
  /// Program torques on body i: none.
  template <class Body, class V3>
  void external(int, double, Body*, const V3&, const V3&) const {}
};

template <typename T>
class TreePasses {
 public:
  using Vec3 = Eigen::Matrix<T, 3, 1>;
  using Vec6 = Eigen::Matrix<T, 6, 1>;
  using Mat3 = Eigen::Matrix<T, 3, 3>;
  using Mat6 = Eigen::Matrix<T, 6, 6>;
  using VecX = Eigen::Matrix<T, Eigen::Dynamic, 1>;
  using Body = TreeBody<T>;
  using RootMomenta = std::vector<Vec6, Eigen::aligned_allocator<Vec6>>;

  /// `articulated`: forwardPass with `dynamics` builds the 6 × 6 inertias
  /// the articulated-body algorithm (solve) needs; without, only what
  /// inverse dynamics reads (J_w and the bias forces).
  TreePasses(const ArticulatedModel& model, const std::vector<JointFrame<T>>& frames, std::vector<Body>& bodies,
             const RootMomenta& root_momentum, bool projecting, bool articulated = true)
      : model_(model),
        frames_(frames),
        bodies_(bodies),
        root_momentum_(root_momentum),
        projecting_(projecting),
        articulated_(articulated) {}

  /// Pass 1: each body's pose, velocity and bias acceleration from its
  /// parent's; with `dynamics` its spatial inertia and bias force (and, with
  /// velocity_terms, the loads' generalized forces); without
  /// velocity_terms the velocity products are left out (a projection).
  /// `State` holds q, u and the spherical and free joints' rotations
  /// (stateRotation(y, k)).
  template <class State, class Loads>
  void forwardPass(double t, const State& y, bool dynamics, bool velocity_terms, const Loads& loads) const;

  /// Passes 2 and 3 with the generalized forces in the bodies' tau; the
  /// ground's acceleration a0 (zero, or −g for a frame that falls).
  void solve(const Vec6& a0, VecX* udot) const;

  /// τ = Sᵀ f of the inverse dynamics at the accelerations u̇ (file comment),
  /// after forwardPass with `dynamics` (velocity_terms on: τ(q, u, u̇), the
  /// forces the motion needs; off: M u̇). The rigid inertias act
  /// in their compact form, f = (J_w α + c × f_lin, m (a_O + α × c)) for
  /// a = (α, a_O): no 6 × 6 products. Trees hanging from the ground.
  void inverseDynamics(const VecX& udot, VecX* tau) const;
  /// Column j of the mass matrix: the inverse dynamics of u̇ = e_j without
  /// the pass's bias terms (after forwardPass with `dynamics`, with or
  /// without velocity_terms, so that one forward pass serves h and M).
  void massMatrixColumn(int j, VecX* column) const;
  /// h = τ(q, u, 0): what the joints transmit at rest accelerations (rate
  /// products and gravity), after forwardPass with `dynamics` and
  /// velocity_terms.
  void biasForces(VecX* h) const;

 private:
  void freeJointPass(const ArticulatedBody& b, Body& d, const Mat3& R, const Vec3& x, const Vec3& w_body,
                     const Vec3& vc, bool velocity_terms, Vec6* Su) const;
  void sphericalJointPass(const ArticulatedBody& b, Body& d, const Mat3& Rp, const Mat3& N, const Vec6& Vp,
                          const Vec3& line, const VecX& u, bool velocity_terms, Vec6* Su) const;
  template <class State, class Loads>
  void coordinateJointPass(int i, double t, const State& y, bool dynamics, bool velocity_terms, const Mat3& Rp,
                           const Vec6& Vp, const Vec3& line, const Loads& loads, Vec6* Su, Vec3* child_anchor) const;
  /// The Newton–Euler passes (n: the coordinates' count); u̇ enters as
  /// `add_column(v, s, &a)`, which adds column s times u̇_v to a body's a.
  template <class AddColumn>
  void newtonEuler(const AddColumn& add_column, bool velocity_terms, int n, VecX* tau) const;
  template <class Loads>
  void inertiaAndBiasForce(int i, double t, bool velocity_terms, const Loads& loads) const;
  /// A child's articulated inertia and force, to its parent (through Pᵀ · P
  /// for a rotation-only child).
  void passToParent(int i, const Mat6& Ia, const Vec6& pa) const;

  const ArticulatedModel& model_;
  const std::vector<JointFrame<T>>& frames_;
  std::vector<Body>& bodies_;
  const RootMomenta& root_momentum_;
  bool projecting_;
  bool articulated_;
};

}  // namespace articulated
}  // namespace lieflow

#include "dynamics/joint_space/tree_passes_impl.hpp"
