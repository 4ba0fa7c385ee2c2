/// \file
/// A constrained multibody system in maximal coordinates, ready to be
/// stepped: the bodies and holonomic joints of a MultibodyModel, the force
/// elements and drives of the joint coordinates, and the gear-type
/// constraints, with the state on the product of the bodies' groups.
///
/// Formulation (README "Joints"): every body keeps its own coordinates —
/// (R, p) ∈ SO(3) × ℝ³ with velocity (v world, ω body), or R ∈ SO(3) with ω
/// for a rotation-only body — and joints are constraints imposed with
/// Lagrange multipliers. The joint coordinates of the Abaqus revolute and
/// universal joints (φ_J; φ₁, φ₂) are functions of the two bodies' relative
/// rotation (dynamics/constraints/revolute_angle.hpp, universal_angles.hpp),
/// continued across ±π by tracking the unwrapped values in the state. On them
/// act, in any combination,
///   * a torsional spring −k (φ − φ₀) and a dashpot −c φ̇ ("to ground": to
///     the joint's zero), and an applied moment M(t): a joint moment M_c does
///     virtual work M_c δφ, so it enters the bodies as J_φᵀ M_c;
///   * a prescribed motion φ(t): the rheonomic constraint φ(q) − φ_p(t) = 0,
///     one more multiplier row (its multiplier is the driving moment).
/// Gear, rack-and-pinion and differential rows (Radioss) act on velocities
/// only: B(q) u = 0.
///
/// Rows that are identically satisfied are not imposed (they would make
/// J M⁻¹ Jᵀ singular): the point rows of a joint whose sides are all
/// rotation-only bodies anchored at their centre of mass (or the ground) —
/// the point cannot move, only the angular rows act; the s, t rows of a gear
/// node hinged to the carrier by a revolute joint, and the s, t rows of a
/// differential whose three nodes are all so hinged (gear.hpp: they vanish
/// identically then).
///
/// Rows are grouped (schur_solver.hpp): first the holonomic joints, then the
/// prescribed coordinates — together the position-level rows Φ(q, t) — then
/// the gears (velocity rows). At acceleration level (index 1):
///   M u̇ + Jᵀ λ = F(t, q, u),    J u̇ = −c + a_p(t),
/// with c the convective terms and a_p the prescribed accelerations; at
/// velocity level J u = b(t) (b the prescribed rates).
///
/// Why maximal coordinates: each body stays on its own group (the Lie-group
/// integrators of integrators/ apply body by body), joints of every type —
/// including closed loops and the gear rows, which reduced coordinates
/// cannot express on velocities — are rows of one sparse Schur complement
/// whose cost is linear along chains, and the reactions are the multipliers.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "dynamics/maximal/multibody_data.hpp"
#include "dynamics/maximal/multibody_group_state.hpp"
#include "dynamics/maximal/multibody_model.hpp"
#include "dynamics/maximal/schur_solver.hpp"
#include "model/time_function.hpp"

namespace lieflow {
namespace multibody {

class MultibodySystem;

/// One joint coordinate's force element rows (for implicit integrators):
/// φ's Jacobian blocks on the joint's two bodies and the spring/damper
/// constants (the applied moment is in forces()).
struct CoordinateElement {
  int joint = -1;
  int coordinate = 0;
  int main = kGround, secondary = kGround;
  Eigen::Matrix<double, 1, 6> J_main, J_secondary;
  double stiffness = 0.0, damping = 0.0;
};

/// Which rows a factorization uses.
enum class RowSet {
  kPosition,  ///< holonomic joints + prescribed coordinates
  kAll,       ///< plus gear rows
};

class MultibodySystem {
 public:
  using State = MultibodyGroupState;
  using Scalar = double;
  /// The row sets, for generic steppers (integrators/constrained_lgvi.hpp).
  using RowSet = ::lieflow::multibody::RowSet;

  /// Checks the drives (one pair per joint; springs, dashpots, moments and
  /// prescribed motion only on revolute/universal coordinates; k, c finite
  /// ≥ 0; rest angles finite) and the gears' bodies (known, distinct, nodes
  /// not the ground, a rack with translational coordinates). Throws
  /// InvalidInput naming the joint and field.
  MultibodySystem(MultibodyModel model, std::vector<CoordinateDrives> drives,
                  std::vector<Gear> gears = {});

  /// A program's torque on body i (body frame, about the CoM) as a function
  /// of time and the body's pose and velocity (UserLoads::BodyTorque).
  using UserTorque = std::function<Eigen::Vector3d(double t, const constraints::BodyPose<double>& pose,
                                                   const constraints::BodyVelocity<double>& velocity)>;
  void setUserTorque(int body, UserTorque torque);
  bool hasUserTorques() const;

  const MultibodyModel& model() const { return model_; }
  const std::vector<CoordinateDrives>& drives() const { return drives_; }
  const std::vector<Gear>& gears() const { return gears_; }
  int bodyCount() const { return static_cast<int>(model_.bodies.size()); }
  /// n = Σ dofs.
  int dofs() const { return n_; }
  int dofBegin(int body) const { return off_[body]; }
  bool rotationOnly(int body) const { return rot_[body] != 0; }
  /// Mass and inertia (about the CoM, body axes) of a body.
  double bodyMass(int body) const { return model_.bodies[body].mass; }
  const Eigen::Matrix3d& bodyInertia(int body) const { return model_.bodies[body].inertia; }
  /// True when some joint coordinate carries a dashpot (forces depend on u).
  bool hasDampers() const;
  /// The coordinates of joint k: 0 (spherical, fixed), 1, 2 or 3 (gimbal).
  int coordinateCount(int k) const;
  /// A gimbal joint k's angles in y (the previous values its angles unwrap near).
  std::array<double, 3> gimbalPrevious(const State& y, int k) const;
  bool hasConstraints() const { return all_groups_.size() > 0; }
  bool hasGears() const { return !gears_.empty(); }
  /// Whether some constraint block changes with the bodies' positions p (the
  /// gear rows and the prismatic joint's dot-2 rows; the other joints' blocks
  /// depend on the rotations only).
  bool jacobiansDependOnPositions() const {
    if (hasGears()) return true;
    for (const Joint& j : model_.joints)
      if (jointKind(j.constraint) == JointKind::kPrismatic || jointKind(j.constraint) == JointKind::kFixed) return true;
    return false;
  }
  int positionRowCount() const;

  /// The state for body poses/velocities (angles set to principal values).
  State makeState(const MultibodyState& bodies) const;
  /// Re-unwraps the joint coordinates of y near their stored values.
  void rebaseAngles(State* y) const;

  // --- Dynamics -----------------------------------------------------------
  /// Generalized forces per dof: (m g + coordinate forces, τ) per body, with
  /// the gyroscopic term −ω × J ω if `gyroscopic`.
  void forces(double t, const State& y, bool gyroscopic, Eigen::VectorXd* F) const;
  /// u̇ and λ (all rows) of the index-1 equations. Returns false with `why`
  /// (naming the joint) when J M⁻¹ Jᵀ is singular.
  bool accelerations(double t, const State& y, Eigen::VectorXd* udot, Eigen::VectorXd* lambda,
                     std::string* why) const;
  /// The velocity field of the RKMK / commutator-free steppers: f = (u, u̇).
  /// A singular constraint system gives a NaN field (the driver reports the
  /// blow-up; accelerations() says why).
  void velocity(double t, const State& y, Eigen::VectorXd* f) const;
  /// Whether f does not depend on t: no prescribed coordinate, applied
  /// moment M(t), program moment or program torque (an implicit stepper
  /// then evaluates its stages at one point once).
  bool autonomous() const;

  // --- Constraints --------------------------------------------------------
  /// Φ(q, t) of the position rows (size positionRowCount()).
  void positionResidual(double t, const State& y, Eigen::VectorXd* phi) const;
  /// max |Φ| (0 without position rows).
  double constraintError(double t, const State& y) const;
  /// max |J u − b| over all rows.
  double velocityConstraintError(double t, const State& y) const;
  /// B(q) u of the gear rows at y (q, u of y), in row order (size: rows of
  /// RowSet::kAll minus positionRowCount(); their targets b are 0). Evaluated
  /// from the constraints directly: leaves the factorizations and the blocks
  /// of schur() untouched.
  void gearVelocityResidual(const State& y, Eigen::VectorXd* r) const;
  /// Fills the Jacobian blocks of all rows at (t, y) into schur(RowSet::kAll)
  /// without factoring S (for Newton iterations that assemble their own
  /// matrix; read them with schur(RowSet::kAll).block(g, s)). Writes Φ of the
  /// position rows (size positionRowCount()) if `phi` and the velocity
  /// targets b of all rows (J u = b) if `b`.
  void constraintJacobians(double t, const State& y, Eigen::VectorXd* phi, Eigen::VectorXd* b) const;
  /// Fills the blocks of the row set at y, sets M⁻¹ and factors S = J M⁻¹ Jᵀ;
  /// afterwards schur(set) gives J, Jᵀ, M⁻¹ and S⁻¹. Also writes the velocity
  /// targets b (J u = b) if `b` and the convective terms minus the prescribed
  /// accelerations (J u̇ = −c) if `c`. Returns false with `why` on a singular S.
  bool factorConstraints(double t, const State& y, RowSet set, std::string* why,
                         Eigen::VectorXd* b = nullptr, Eigen::VectorXd* c = nullptr) const;
  SchurSolver& schur(RowSet set) const { return set == RowSet::kAll || !hasGears() ? data_.all : data_.pos; }
  /// Velocity projection: u ← u − M⁻¹ Jᵀ S⁻¹ (J u − b) (all rows, at y's q).
  bool projectVelocities(double t, State* y, std::string* why) const;
  /// The position tolerance that can be met at y: max(tolerance, the
  /// round-off of the point rows). A point row Φ = (p_a + R_a r_a) − (p_b +
  /// R_b r_b) is computed from positions of size ‖p‖∞, so it cannot be
  /// brought below about kPositionRoundoffUlps · ε · ‖p‖∞ (7e-12 at the
  /// 50 km of a 100000-rod chain, where a fixed 1e-12 can never be met).
  double achievablePositionTolerance(const State& y, double tolerance) const;
  static constexpr double kPositionRoundoffUlps = 16.0;
  /// A held factorization is reused by projectPositions while each
  /// iteration reduces max |Φ| at least this much.
  static constexpr double kStaleContraction = 0.1;

  /// Position projection onto Φ = 0 (M-orthogonal, simplified Newton with S
  /// factored at the start point, or the factorization the solver already
  /// holds from nearby positions while it contracts by kStaleContraction per
  /// iteration): stops when max |Φ| ≤ the achievable tolerance; false with
  /// `why` if max_iterations pass first or S is singular.
  bool projectPositions(double t, State* y, double tolerance, int max_iterations, int* iterations,
                        std::string* why) const;

  /// Spring/dashpot elements with their φ Jacobians at y (implicit methods),
  /// into *out (its storage reused).
  void coordinateElementsInto(const State& y, std::vector<CoordinateElement>* out) const;

  // --- Observables --------------------------------------------------------
  /// Kinetic + gravity potential + spring energy.
  double energy(const State& y) const;
  double energy(double /*t*/, const State& y) const { return energy(y); }
  /// The sum of the magnitudes of the energy's terms (kinetic, m ‖g‖ ‖p‖ per
  /// body, springs): the scale of the energy's round-off (DriftTracker).
  double energyTermScale(const State& y) const;
  Eigen::Vector3d spatialAngularMomentum(const State& y) const { return angularMomentum(y); }
  /// Σ (p × m v + R J ω), the spatial angular momentum about the world origin.
  Eigen::Vector3d angularMomentum(const State& y) const;
  /// True when no external moment acts about the origin: no gravity on a
  /// translating body, no joint or gear to the ground, no force passed to the
  /// support of a rotation-only body (see the .cpp).
  bool conservesAngularMomentum() const;
  /// Σ R J ω + (p − x) × m (v − ẋ): the angular momentum about a point x
  /// moving at ẋ (differences first, so that far from the origin it keeps
  /// its digits).
  Eigen::Vector3d momentumAbout(const State& y, const Eigen::Vector3d& point, const Eigen::Vector3d& velocity) const;
  /// Σ R J ω + (p − c) × m (v − v_c), the angular momentum about the centre
  /// of mass c of the bodies (all translating when it is asked for).
  Eigen::Vector3d centreOfMassMomentum(const State& y) const;
  /// True when the only external force is uniform gravity: every body
  /// translates, no joint or gear to the ground, no program's torques; then
  /// centreOfMassMomentum is conserved.
  bool conservesCentreOfMassMomentum() const;
  /// Σ c φ̇² ≥ 0, the power the joints' dashpots dissipate.
  double dissipatedPower(const State& y) const;
  /// True when some coordinate has a dashpot and the dashpots are the only
  /// non-conservative forces (no applied or program moments, no prescribed
  /// motion, no program torques): energy + dissipated work is conserved.
  bool conservesEnergyBalance() const;
  /// Joint angles, rates and moments about the joint axes at (t, y): the
  /// moment on the main body about each axis (M_J = M_M · a, README), the
  /// constraint reaction plus the joint's force elements. Uses the
  /// acceleration solve for the multipliers.
  std::vector<JointOutput> jointOutputs(double t, const State& y) const;

 private:
  /// energy() and energyTermScale() in one pass over the bodies.
  std::pair<double, double> energyAndTermScale(const State& y) const;
  struct CoordinateRef {
    int joint, coordinate;
  };
  void validate() const;
  void poses(const State& y, int main, int secondary, BodyPose<double>* a, BodyPose<double>* b,
             BodyVelocity<double>* va, BodyVelocity<double>* vb) const;
  /// φ (unwrapped near y.angles), and its Jacobian row blocks on (main, secondary).
  double coordinate(const State& y, int k, int i, Eigen::Matrix<double, 1, 6>* Ja,
                    Eigen::Matrix<double, 1, 6>* Jb) const;
  /// Every coordinate of joint k at once (a universal joint's two angles,
  /// a gimbal's three, come from one decomposition of the relative
  /// rotation): φ_i and, when Ja is given, their Jacobian rows. Returns
  /// coordinateCount(k).
  using CoordinateRows = std::array<Eigen::Matrix<double, 1, 6>, kMaxJointCoordinates>;
  int coordinates(const State& y, int k, std::array<double, kMaxJointCoordinates>* phi, CoordinateRows* Ja,
                  CoordinateRows* Jb) const;
  double coordinateConvective(const State& y, int k, int i) const;
  /// φ̇ = J_a u_a + J_b u_b from a coordinate's Jacobian rows (bodies main,
  /// secondary; kGround contributes nothing).
  double coordinateRate(const State& y, int main, int secondary, const Eigen::Matrix<double, 1, 6>& Ja,
                        const Eigen::Matrix<double, 1, 6>& Jb) const;
  /// F += Jᵀ M on `body`'s coordinates (only the δθ columns of a
  /// rotation-only body; nothing for kGround).
  void addCoordinateForce(int body, const Eigen::Matrix<double, 1, 6>& J, double M, Eigen::VectorXd* F) const;
  /// The poses and velocities of gear constraint C's nodes at y (the
  /// ground's for a ground node); with `as_multiplied`, a rotation-only
  /// body's v is zeroed, as multiplyJ sees it (no δp columns).
  template <typename C>
  void gearNodes(const Gear& gear, const State& y, bool as_multiplied, typename C::Poses* X,
                 typename C::Velocities* V) const {
    for (std::size_t s = 0; s < C::kBodies; ++s) {
      const int body = gear.bodies[s];
      (*X)[s] = body == kGround ? constraints::groundPose<double>() : y.bodies.poses[body];
      (*V)[s] = body == kGround ? constraints::groundVelocity<double>() : y.bodies.velocities[body];
      if (as_multiplied && body != kGround && rot_[body]) (*V)[s].v.setZero();
    }
  }
  /// Writes the Jacobian blocks of the groups into S (if `jacobians`) and Φ,
  /// the velocity targets b and the convective terms c where asked.
  void fillGroups(double t, const State& y, SchurSolver& S, bool gears, Eigen::VectorXd* phi,
                  Eigen::VectorXd* b, Eigen::VectorXd* c, bool jacobians = true) const;
  /// True when y's poses are bitwise those of the cached factorization.
  bool samePoses(const State& y) const;

  /// Rows of joint k's constraint that are imposed: all but the first
  /// skip_rows_[k] (3 when the point rows are identically satisfied).
  std::vector<int> skip_rows_;
  /// Rows of each gear constraint that are imposed.
  std::vector<std::vector<int>> gear_rows_;

  MultibodyModel model_;
  std::vector<CoordinateDrives> drives_;
  std::vector<Gear> gears_;
  std::vector<UserTorque> user_torques_;  ///< per body, empty: none
  std::vector<char> rot_;
  std::vector<int> off_;
  int n_ = 0;
  std::vector<CoordinateRef> prescribed_;
  std::vector<RowGroup> all_groups_, pos_groups_;
  /// The workspace every evaluation writes (multibody_data.hpp).
  mutable MultibodyData data_;
};

}  // namespace multibody
}  // namespace lieflow
