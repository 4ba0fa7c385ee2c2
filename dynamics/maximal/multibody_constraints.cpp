// MultibodySystem: constraint residuals, Jacobians and the position and
// velocity projections.
#include "dynamics/maximal/multibody_system.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace lieflow {
namespace multibody {

using constraints::BodyPose;
using constraints::BodyVelocity;
using Row6 = Eigen::Matrix<double, 1, 6>;

// --- Constraints ---------------------------------------------------------------

void MultibodySystem::positionResidual(double t, const State& y, Eigen::VectorXd* phi) const {
  phi->resize(positionRowCount());
  int r = 0;
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const Joint& j = model_.joints[k];
    const int rows = constraintRows(j.constraint) - skip_rows_[k];
    if (rows == 0) continue;
    BodyPose<double> pa, pb;
    poses(y, j.main, j.secondary, &pa, &pb, nullptr, nullptr);
    if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint)) {
      constraints::RevoluteJoint<double>::Residual res;  // the fused evaluation, Φ only
      rev->evaluate(pa, pb, nullptr, nullptr, &res, nullptr, nullptr);
      phi->segment(r, rows) = res.tail(rows);
    } else {
      std::visit([&](const auto& con) { phi->segment(r, rows) = con.residual(pa, pb).tail(rows); }, j.constraint);
    }
    r += rows;
  }
  for (const CoordinateRef& p : prescribed_)
    (*phi)[r++] = coordinate(y, p.joint, p.coordinate, nullptr, nullptr) -
                  (*drives_[p.joint][p.coordinate].prescribed)(t);
}

double MultibodySystem::constraintError(double t, const State& y) const {
  if (pos_groups_.empty()) return 0.0;
  positionResidual(t, y, &data_.residual);
  return data_.residual.lpNorm<Eigen::Infinity>();
}

double MultibodySystem::velocityConstraintError(double t, const State& y) const {
  if (!hasConstraints()) return 0.0;
  SchurSolver& S = data_.all;
  Eigen::VectorXd b(S.rows());  // fillGroups writes segments: size it first
  fillGroups(t, y, S, hasGears(), nullptr, &b, nullptr);
  Eigen::VectorXd Ju;
  S.multiplyJ(y.velocities(), Ju);
  return (Ju - b).lpNorm<Eigen::Infinity>();
}

void MultibodySystem::constraintJacobians(double t, const State& y, Eigen::VectorXd* phi,
                                          Eigen::VectorXd* b) const {
  // Position rows come first in data_.all, so Φ fills the head of the row range.
  if (phi) phi->resize(positionRowCount());
  if (b) b->resize(data_.all.rows());
  fillGroups(t, y, data_.all, hasGears(), phi, b, nullptr);
}

void MultibodySystem::gearVelocityResidual(const State& y, Eigen::VectorXd* r) const {
  int rows = 0;
  for (const std::vector<int>& sel : gear_rows_) rows += static_cast<int>(sel.size());
  r->resize(rows);
  int r0 = 0;
  for (std::size_t gi = 0; gi < gears_.size(); ++gi) {
    const Gear& gear = gears_[gi];
    const std::vector<int>& sel = gear_rows_[gi];  // the imposed rows, as in fillGroups
    std::visit(
        [&](const auto& con) {
          using C = std::decay_t<decltype(con)>;
          typename C::Poses X;
          typename C::Velocities V;
          gearNodes<C>(gear, y, true, &X, &V);  // no δp columns (as multiplyJ)
          const auto Bu = con.velocity(X, V);
          for (std::size_t k = 0; k < sel.size(); ++k) (*r)[r0 + static_cast<int>(k)] = Bu[sel[k]];
          r0 += static_cast<int>(sel.size());
        },
        gear.constraint);
  }
}

bool MultibodySystem::projectVelocities(double t, State* y, std::string* why) const {
  if (!hasConstraints()) return true;
  Eigen::VectorXd& b = data_.b;
  if (!factorConstraints(t, *y, RowSet::kAll, why, &b, nullptr)) return false;
  SchurSolver& S = data_.all;
  Eigen::VectorXd& u = data_.u;
  y->velocitiesInto(&u);
  S.multiplyJ(u, data_.rhs);
  data_.rhs -= b;
  S.solve(data_.rhs, data_.lam);
  data_.tmp.setZero(n_);
  S.addJTranspose(data_.lam, 1.0, data_.tmp);
  S.applyInverseMass(data_.tmp, data_.y);
  u -= data_.y;
  y->setVelocities(u);
  return true;
}

double MultibodySystem::achievablePositionTolerance(const State& y, double tolerance) const {
  double extent = 1.0;
  for (int i = 0; i < bodyCount(); ++i)
    if (!rotationOnly(i)) extent = std::max(extent, y.bodies.poses[i].p.lpNorm<Eigen::Infinity>());
  return std::max(tolerance, kPositionRoundoffUlps * std::numeric_limits<double>::epsilon() * extent);
}

bool MultibodySystem::projectPositions(double t, State* y, double requested_tolerance, int max_iterations,
                                       int* iterations, std::string* why) const {
  if (iterations) *iterations = 0;
  if (pos_groups_.empty()) return true;
  const double tolerance = achievablePositionTolerance(*y, requested_tolerance);
  Eigen::VectorXd& phi = data_.phi;
  positionResidual(t, *y, &phi);
  if (phi.lpNorm<Eigen::Infinity>() <= tolerance) return true;
  SchurSolver& S = schur(RowSet::kPosition);
  // A factorization of the position rows at nearby positions (the last
  // stage of the step just taken) serves the simplified Newton as well as
  // one at y: the iteration contracts by a factor of the order of the
  // distance between the two. It is kept while each iteration reduces max |Φ|
  // by kStaleContraction; otherwise y goes back to where that iteration
  // started and S is factored there.
  bool fresh = !(data_.factor_cache.valid && data_.factor_cache.solver == &S);
  if (fresh && !factorConstraints(t, *y, RowSet::kPosition, why)) return false;
  Eigen::VectorXd& d = data_.projection_step;
  d.setZero(2 * n_);
  double previous = phi.lpNorm<Eigen::Infinity>();
  int fresh_iterations = 0;
  for (int it = 1; it <= max_iterations; ++it) {
    if (!fresh) data_.projection_backup = *y;
    // Δq = −M⁻¹ Jᵀ S⁻¹ Φ (simplified Newton: J and S held fixed).
    S.solve(phi, data_.lam);
    data_.tmp.setZero(n_);
    S.addJTranspose(data_.lam, -1.0, data_.tmp);
    S.applyInverseMass(data_.tmp, data_.y);
    d.head(n_) = data_.y;
    y->rplusInPlace(d);
    if (iterations) *iterations = it;
    positionResidual(t, *y, &phi);
    const double err = phi.lpNorm<Eigen::Infinity>();
    if (err <= tolerance) return true;
    if (!fresh) {
      if (err <= kStaleContraction * previous) {
        previous = err;
        continue;
      }
      *y = data_.projection_backup;
      positionResidual(t, *y, &phi);
      if (!factorConstraints(t, *y, RowSet::kPosition, why)) return false;
      fresh = true;
      previous = phi.lpNorm<Eigen::Infinity>();
      continue;
    }
    ++fresh_iterations;
    if (!(err < previous) && fresh_iterations > 2) break;  // not contracting (or NaN)
    previous = err;
  }
  if (why) {
    std::ostringstream s;
    s << "position projection did not converge: max |Phi| = " << phi.lpNorm<Eigen::Infinity>() << " after "
      << (iterations ? *iterations : max_iterations) << " iterations (tolerance " << tolerance
      << "); the step left the constraints too far to return, as beyond the integrator's stability limit";
    *why = s.str();
  }
  return false;
}

void MultibodySystem::coordinateElementsInto(const State& y, std::vector<CoordinateElement>* out_ptr) const {
  std::vector<CoordinateElement>& out = *out_ptr;
  out.clear();
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const int nc = coordinateCount(static_cast<int>(k));
    bool any = false;
    for (int i = 0; i < nc; ++i) any = any || drives_[k][i].stiffness != 0.0 || drives_[k][i].damping != 0.0;
    if (!any) continue;
    std::array<double, kMaxJointCoordinates> phi;
    CoordinateRows Ja, Jb;
    coordinates(y, static_cast<int>(k), &phi, &Ja, &Jb);
    for (int i = 0; i < nc; ++i) {
      const CoordinateDrive& d = drives_[k][i];
      if (d.stiffness == 0.0 && d.damping == 0.0) continue;
      CoordinateElement e;
      e.joint = static_cast<int>(k);
      e.coordinate = i;
      e.main = model_.joints[k].main;
      e.secondary = model_.joints[k].secondary;
      e.J_main = Ja[i];
      e.J_secondary = Jb[i];
      e.stiffness = d.stiffness;
      e.damping = d.damping;
      out.push_back(e);
    }
  }
}

}  // namespace multibody
}  // namespace lieflow
