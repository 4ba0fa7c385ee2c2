#include "joints/multibody/multibody_system.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "integrators/rigid_body_state.hpp"

namespace lieflow {
namespace multibody {

using constraints::BodyPose;
using constraints::BodyVelocity;
using Row6 = Eigen::Matrix<double, 1, 6>;

// --- State -------------------------------------------------------------------

MultibodyGroupState::Tangent MultibodyGroupState::zeroTangent() const {
  return Tangent::Zero(2 * system->dofs());
}

int MultibodyGroupState::tangentSize() const { return 2 * system->dofs(); }

MultibodyGroupState MultibodyGroupState::rplus(const Tangent& d) const {
  MultibodyGroupState out = *this;
  out.rplusInPlace(d);
  return out;
}

void MultibodyGroupState::rplusInPlace(const Tangent& d) {
  const int n = system->dofs();
  for (int i = 0; i < system->bodyCount(); ++i) {
    const int o = system->dofBegin(i);
    BodyPose<double>& P = bodies.poses[i];
    BodyVelocity<double>& V = bodies.velocities[i];
    if (system->rotationOnly(i)) {
      P.R = P.R * SO3d::exp(d.segment<3>(o));
      V.omega += d.segment<3>(n + o);
    } else {
      P.p += d.segment<3>(o);
      P.R = P.R * SO3d::exp(d.segment<3>(o + 3));
      V.v += d.segment<3>(n + o);
      V.omega += d.segment<3>(n + o + 3);
    }
  }
  system->rebaseAngles(this);
}

MultibodyGroupState::Tangent MultibodyGroupState::dexpInvRight(const Tangent& theta, const Tangent& v,
                                                               int order) const {
  Tangent out;
  dexpInvRightInto(theta, v, order, &out);
  return out;
}

void MultibodyGroupState::dexpInvRightInto(const Tangent& theta, const Tangent& v, int order, Tangent* out) const {
  *out = v;
  for (int i = 0; i < system->bodyCount(); ++i) {
    const int o = system->dofBegin(i) + (system->rotationOnly(i) ? 0 : 3);
    out->segment<3>(o) = detail::so3DexpInvRight<double>(theta.segment<3>(o), v.segment<3>(o), order);
  }
}

MultibodyGroupState::Tangent MultibodyGroupState::magnitude() const {
  const int n = system->dofs();
  Tangent m(2 * n);
  m.head(n).setOnes();
  m.tail(n) = velocities().cwiseAbs();
  return m;
}

Eigen::VectorXd MultibodyGroupState::velocities() const {
  Eigen::VectorXd u;
  velocitiesInto(&u);
  return u;
}

void MultibodyGroupState::velocitiesInto(Eigen::VectorXd* out) const {
  Eigen::VectorXd& u = *out;
  u.resize(system->dofs());
  for (int i = 0; i < system->bodyCount(); ++i) {
    const int o = system->dofBegin(i);
    if (system->rotationOnly(i)) {
      u.segment<3>(o) = bodies.velocities[i].omega;
    } else {
      u.segment<3>(o) = bodies.velocities[i].v;
      u.segment<3>(o + 3) = bodies.velocities[i].omega;
    }
  }
}

void MultibodyGroupState::setVelocities(const Eigen::VectorXd& u) {
  for (int i = 0; i < system->bodyCount(); ++i) {
    const int o = system->dofBegin(i);
    if (system->rotationOnly(i)) {
      bodies.velocities[i].omega = u.segment<3>(o);
    } else {
      bodies.velocities[i].v = u.segment<3>(o);
      bodies.velocities[i].omega = u.segment<3>(o + 3);
    }
  }
}

bool isFinite(const MultibodyGroupState& y) {
  for (std::size_t i = 0; i < y.bodies.poses.size(); ++i) {
    if (!y.bodies.poses[i].p.allFinite() || !y.bodies.poses[i].R.quaternion().coeffs().allFinite() ||
        !y.bodies.velocities[i].v.allFinite() || !y.bodies.velocities[i].omega.allFinite())
      return false;
  }
  return true;
}

// --- Construction --------------------------------------------------------------

MultibodySystem::MultibodySystem(MultibodyModel model, std::vector<std::array<CoordinateDrive, 2>> drives,
                                 std::vector<Gear> gears)
    : model_(std::move(model)), drives_(std::move(drives)), gears_(std::move(gears)) {
  if (drives_.empty()) drives_.resize(model_.joints.size());
  model_.validateModel();
  validate();
  const int nb = bodyCount();
  rot_.resize(nb);
  off_.assign(nb + 1, 0);
  for (int i = 0; i < nb; ++i) {
    rot_[i] = model_.bodies[i].rotation_only ? 1 : 0;
    off_[i + 1] = off_[i] + model_.bodies[i].dofs();
  }
  n_ = off_[nb];
  // Identically satisfied rows (see the header).
  auto fixedPoint = [&](int body, const Eigen::Vector3d& anchor) {
    return body == kGround || (rot_[body] && anchor.norm() <= 1e-12);
  };
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const Joint& j = model_.joints[k];
    const auto& point = std::visit(
        [](const auto& con) -> const constraints::SphericalJoint<double>& {
          if constexpr (std::is_same_v<std::decay_t<decltype(con)>, constraints::SphericalJoint<double>>)
            return con;
          else
            return con.point;
        },
        j.constraint);
    const bool trivial = fixedPoint(j.main, point.anchor_main) && fixedPoint(j.secondary, point.anchor_secondary);
    skip_rows_.push_back(trivial ? 3 : 0);
    RowGroup g;
    g.bodies = {{j.main, j.secondary, kGround, kGround}};
    g.rows = constraintRows(j.constraint) - skip_rows_.back();
    pos_groups_.push_back(g);
  }
  // A node is hinged to its carrier when a revolute joint joins them about
  // the node's r axis (parallel to 1e-9 in the node's frame).
  auto hingedToCarrier = [&](int node, int carrier, const Eigen::Vector3d& r_node) {
    for (const Joint& j : model_.joints) {
      const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint);
      if (!rev) continue;
      Eigen::Vector3d axis_node;
      if (j.main == node && j.secondary == carrier)
        axis_node = rev->axis_main;
      else if (j.main == carrier && j.secondary == node)
        axis_node = rev->axis_secondary;
      else
        continue;
      if (std::abs(axis_node.dot(r_node)) >= 1.0 - 1e-9) return true;
    }
    return false;
  };
  for (const Gear& gear : gears_) {
    std::vector<int> rows;
    if (gear.constraint.index() == 0) {  // gear: r row, node 1 s/t, node 2 s/t
      const auto& gj = std::get<constraints::GearJoint<double>>(gear.constraint);
      rows.push_back(0);
      for (int node = 1; node <= 2; ++node)
        if (!hingedToCarrier(gear.bodies[node], gear.bodies[0], node == 1 ? gj.node1.r : gj.node2.r)) {
          rows.push_back(2 * node - 1);
          rows.push_back(2 * node);
        }
    } else if (gear.constraint.index() == 1) {  // rack and pinion: both rows
      rows = {0, 1};
    } else {  // differential: r row; s, t rows unless every node is hinged
      const auto& dj = std::get<constraints::DifferentialJoint<double>>(gear.constraint);
      rows.push_back(0);
      const Eigen::Vector3d r[3] = {dj.node1.r, dj.node2.r, dj.node3.r};
      bool all = true;
      for (int node = 1; node <= 3; ++node)
        all = all && hingedToCarrier(gear.bodies[node], gear.bodies[0], r[node - 1]);
      if (!all) rows.insert(rows.end(), {1, 2});
    }
    gear_rows_.push_back(rows);
  }
  for (std::size_t k = 0; k < model_.joints.size(); ++k)
    for (int i = 0; i < coordinateCount(static_cast<int>(k)); ++i)
      if (drives_[k][i].prescribed) {
        prescribed_.push_back({static_cast<int>(k), i});
        RowGroup g;
        g.bodies = {{model_.joints[k].main, model_.joints[k].secondary, kGround, kGround}};
        g.rows = 1;
        pos_groups_.push_back(g);
      }
  all_groups_ = pos_groups_;
  for (std::size_t i = 0; i < gears_.size(); ++i) {
    RowGroup g;
    g.bodies = gears_[i].bodies;
    g.rows = static_cast<int>(gear_rows_[i].size());
    all_groups_.push_back(g);
  }
  all_.setup(rot_, all_groups_);
  if (hasGears()) pos_.setup(rot_, pos_groups_);
}

int MultibodySystem::coordinateCount(int k) const {
  switch (model_.joints[k].constraint.index()) {
    case 1: return 1;  // revolute
    case 2: return 2;  // universal
    default: return 0;
  }
}

bool MultibodySystem::hasDampers() const {
  for (std::size_t k = 0; k < model_.joints.size(); ++k)
    for (int i = 0; i < coordinateCount(static_cast<int>(k)); ++i)
      if (drives_[k][i].damping != 0.0) return true;
  return false;
}

int MultibodySystem::positionRowCount() const {
  int m = 0;
  for (const RowGroup& g : pos_groups_) m += g.rows;
  return m;
}

void MultibodySystem::validate() const {
  if (drives_.size() != model_.joints.size())
    throw InvalidInput("joints", "one drive pair per joint expected");
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const std::string label = model_.jointLabel(static_cast<int>(k));
    const int nc = coordinateCount(static_cast<int>(k));
    for (int i = 0; i < 2; ++i) {
      const CoordinateDrive& d = drives_[k][i];
      const bool used = d.hasForce() || d.prescribed.has_value() || d.rest_angle != 0.0;
      if (i >= nc && used)
        throw InvalidInput(label, nc == 0 ? "a spherical joint has no joint coordinate to carry a spring, "
                                            "damper, moment or prescribed motion"
                                          : "a revolute joint has one joint coordinate");
      if (!(std::isfinite(d.stiffness) && d.stiffness >= 0.0))
        throw InvalidInput(label + ".spring.stiffness", "must be finite and >= 0");
      if (!std::isfinite(d.rest_angle)) throw InvalidInput(label + ".spring.rest_angle", "must be finite");
      if (!(std::isfinite(d.damping) && d.damping >= 0.0))
        throw InvalidInput(label + ".damper.damping", "must be finite and >= 0");
    }
  }
  const int nb = bodyCount();
  for (const Gear& g : gears_) {
    const int nodes =
        std::visit([](const auto& c) { return static_cast<int>(std::decay_t<decltype(c)>::kBodies); }, g.constraint);
    for (int s = 0; s < nodes; ++s) {
      const int b = g.bodies[s];
      const std::string field = g.name + (s == 0 ? ".carrier" : ".node" + std::to_string(s));
      if (b < kGround || b >= nb) throw InvalidInput(field, "unknown body index " + std::to_string(b));
      if (s > 0 && b == kGround)
        throw InvalidInput(field, "a gear node must be a body with rotary inertia, not the ground");
      for (int r = 0; r < s; ++r)
        if (g.bodies[r] == b && b != kGround)
          throw InvalidInput(field, "the same body appears twice in one gear constraint");
    }
    if (g.constraint.index() == 1 && model_.bodies[g.bodies[2]].rotation_only)
      throw InvalidInput(g.name + ".node2", "the rack must have translational coordinates (not rotation_only)");
  }
}

MultibodyGroupState MultibodySystem::makeState(const MultibodyState& bodies) const {
  model_.validateState(bodies);
  State y;
  y.bodies = bodies;
  y.system = this;
  // Principal values: unwrapped around 0.
  y.angles.assign(2 * model_.joints.size(), 0.0);
  rebaseAngles(&y);
  return y;
}

void MultibodySystem::poses(const State& y, int main, int secondary, BodyPose<double>* a, BodyPose<double>* b,
                            BodyVelocity<double>* va, BodyVelocity<double>* vb) const {
  *a = main == kGround ? constraints::groundPose<double>() : y.bodies.poses[main];
  *b = secondary == kGround ? constraints::groundPose<double>() : y.bodies.poses[secondary];
  if (va) *va = main == kGround ? constraints::groundVelocity<double>() : y.bodies.velocities[main];
  if (vb) *vb = secondary == kGround ? constraints::groundVelocity<double>() : y.bodies.velocities[secondary];
}

double MultibodySystem::coordinate(const State& y, int k, int i, Row6* Ja, Row6* Jb) const {
  const Joint& j = model_.joints[k];
  BodyPose<double> a, b;
  poses(y, j.main, j.secondary, &a, &b, nullptr, nullptr);
  if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint)) {
    if (Ja) {
      const auto J = constraints::revoluteAngleJacobians(*rev, a, b);
      *Ja = J[0];
      *Jb = J[1];
    }
    return constraints::revoluteAngle(*rev, a, b, y.angles[2 * k]);
  }
  const auto& uni = std::get<constraints::UniversalJoint<double>>(j.constraint);
  if (Ja) {
    const auto J = constraints::universalAngleJacobians(uni, a, b);
    *Ja = J[0].row(i);
    *Jb = J[1].row(i);
  }
  const auto ang = constraints::universalAngles(uni, a, b, y.angles[2 * k], y.angles[2 * k + 1]);
  return i == 0 ? ang.phi1 : ang.phi2;
}

double MultibodySystem::coordinateConvective(const State& y, int k, int i) const {
  const Joint& j = model_.joints[k];
  BodyPose<double> a, b;
  BodyVelocity<double> va, vb;
  poses(y, j.main, j.secondary, &a, &b, &va, &vb);
  if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint))
    return constraints::revoluteAngleConvective(*rev, a, b, va, vb);
  const auto& uni = std::get<constraints::UniversalJoint<double>>(j.constraint);
  return constraints::universalAngleConvective(uni, a, b, va, vb)[i];
}

void MultibodySystem::rebaseAngles(State* y) const {
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const int nc = coordinateCount(static_cast<int>(k));
    if (nc == 0) continue;
    const Joint& j = model_.joints[k];
    BodyPose<double> a, b;
    poses(*y, j.main, j.secondary, &a, &b, nullptr, nullptr);
    if (nc == 1) {
      y->angles[2 * k] = constraints::revoluteAngle(std::get<constraints::RevoluteJoint<double>>(j.constraint), a,
                                                    b, y->angles[2 * k]);
    } else {
      const auto ang = constraints::universalAngles(std::get<constraints::UniversalJoint<double>>(j.constraint), a,
                                                    b, y->angles[2 * k], y->angles[2 * k + 1]);
      y->angles[2 * k] = ang.phi1;
      y->angles[2 * k + 1] = ang.phi2;
    }
  }
}

bool MultibodySystem::samePoses(const State& y) const {
  const auto& P = y.bodies.poses;
  if (P.size() != factor_cache_.poses.size()) return false;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P[i].p != factor_cache_.poses[i].p ||
        P[i].R.quaternion().coeffs() != factor_cache_.poses[i].R.quaternion().coeffs())
      return false;
  return true;
}

// --- Dynamics ------------------------------------------------------------------

void MultibodySystem::forces(double t, const State& y, bool gyroscopic, Eigen::VectorXd* F) const {
  F->setZero(n_);
  for (int i = 0; i < bodyCount(); ++i) {
    const RigidBody& body = model_.bodies[i];
    const int o = off_[i];
    const Eigen::Vector3d& w = y.bodies.velocities[i].omega;
    const int r = rot_[i] ? 0 : 3;
    if (!rot_[i]) F->segment<3>(o) = body.mass * model_.gravity;
    if (gyroscopic) F->segment<3>(o + r) = -w.cross(body.inertia * w);
  }
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const int nc = coordinateCount(static_cast<int>(k));
    const Joint& j = model_.joints[k];
    for (int i = 0; i < nc; ++i) {
      const CoordinateDrive& d = drives_[k][i];
      if (!d.hasForce()) continue;
      Row6 Ja, Jb;
      const double phi = coordinate(y, static_cast<int>(k), i, &Ja, &Jb);
      double phidot = 0.0;
      if (j.main != kGround) phidot += Ja.tail<3>().dot(y.bodies.velocities[j.main].omega);
      if (j.secondary != kGround) phidot += Jb.tail<3>().dot(y.bodies.velocities[j.secondary].omega);
      double M = -d.stiffness * (phi - d.rest_angle) - d.damping * phidot;
      if (d.moment) M += (*d.moment)(t);
      // Generalized force J_φᵀ M (φ's Jacobian has no translation columns).
      if (j.main != kGround) F->segment<3>(off_[j.main] + (rot_[j.main] ? 0 : 3)) += Ja.tail<3>().transpose() * M;
      if (j.secondary != kGround)
        F->segment<3>(off_[j.secondary] + (rot_[j.secondary] ? 0 : 3)) += Jb.tail<3>().transpose() * M;
    }
  }
}

void MultibodySystem::fillGroups(double t, const State& y, SchurSolver& S, bool gears, Eigen::VectorXd* phi,
                                 Eigen::VectorXd* b, Eigen::VectorXd* c, bool jacobians) const {
  // New blocks no longer match the factorization held by the solvers.
  if (jacobians) factor_cache_.valid = false;
  const int nj = static_cast<int>(model_.joints.size());
  int g = 0;
  for (int k = 0; k < nj; ++k, ++g) {
    const Joint& j = model_.joints[k];
    BodyPose<double> pa, pb;
    BodyVelocity<double> va, vb;
    poses(y, j.main, j.secondary, &pa, &pb, &va, &vb);
    const int r0 = S.rowBegin(g), rows = S.groupRows(g);
    if (rows == 0) continue;
    std::visit(
        [&](const auto& con) {
          if (jacobians) {
            const auto J = con.jacobians(pa, pb);
            S.block(g, 0) = J[0].bottomRows(rows);
            S.block(g, 1) = J[1].bottomRows(rows);
          }
          if (phi) phi->segment(r0, rows) = con.residual(pa, pb).tail(rows);
          if (b) b->segment(r0, rows).setZero();
          if (c) c->segment(r0, rows) = con.convective(pa, pb, va, vb).tail(rows);
        },
        j.constraint);
  }
  for (const CoordinateRef& p : prescribed_) {
    const TimeFunction& f = *drives_[p.joint][p.coordinate].prescribed;
    if (jacobians || phi) {
      Row6 Ja, Jb;
      const double value = coordinate(y, p.joint, p.coordinate, &Ja, &Jb);
      if (jacobians) {
        S.block(g, 0) = Ja;
        S.block(g, 1) = Jb;
      }
      if (phi) (*phi)[S.rowBegin(g)] = value - f(t);
    }
    const int r0 = S.rowBegin(g);
    if (b) (*b)[r0] = f.derivative(t);
    if (c) (*c)[r0] = coordinateConvective(y, p.joint, p.coordinate) - f.secondDerivative(t);
    ++g;
  }
  if (!gears) return;
  for (std::size_t gi = 0; gi < gears_.size(); ++gi) {
    const Gear& gear = gears_[gi];
    const std::vector<int>& sel = gear_rows_[gi];
    std::visit(
        [&](const auto& con) {
          using C = std::decay_t<decltype(con)>;
          typename C::Poses X;
          typename C::Velocities V;
          for (std::size_t s = 0; s < C::kBodies; ++s) {
            const int body = gear.bodies[s];
            X[s] = body == kGround ? constraints::groundPose<double>() : y.bodies.poses[body];
            V[s] = body == kGround ? constraints::groundVelocity<double>() : y.bodies.velocities[body];
          }
          const int rows = static_cast<int>(sel.size());
          if (jacobians) {
            const auto B = con.rows(X);
            for (std::size_t s = 0; s < C::kBodies; ++s) {
              GroupBlock& blk = S.block(g, static_cast<int>(s));
              blk.resize(rows, 6);
              for (int r = 0; r < rows; ++r) blk.row(r) = B[s].row(sel[r]);
            }
          }
          const int r0 = S.rowBegin(g);
          if (b) b->segment(r0, rows).setZero();
          if (c) {
            const auto cc = con.convective(X, V);
            for (int r = 0; r < rows; ++r) (*c)[r0 + r] = cc[sel[r]];
          }
        },
        gear.constraint);
    ++g;
  }
}

bool MultibodySystem::factorConstraints(double t, const State& y, RowSet set, std::string* why,
                                        Eigen::VectorXd* b, Eigen::VectorXd* c) const {
  SchurSolver& S = schur(set);
  const bool gears = &S == &all_ && hasGears();
  if (b) b->resize(S.rows());
  if (c) c->resize(S.rows());
  if (factor_cache_.valid && factor_cache_.solver == &S && samePoses(y)) {
    // S already holds J(q) and its factorization at these positions (the
    // velocity projection of the last step, for the first stage of the
    // next): only the velocity-dependent targets are new.
    if (b || c) fillGroups(t, y, S, gears, nullptr, b, c, false);
    return true;
  }
  for (int i = 0; i < bodyCount(); ++i) {
    const RigidBody& body = model_.bodies[i];
    S.setInverseMass(i, body.rotation_only ? 0.0 : 1.0 / body.mass, body.inertia.inverse());
  }
  fillGroups(t, y, S, gears, nullptr, b, c);
  const FactorStatus st = S.factor();
  if (st.ok) {
    factor_cache_.valid = true;
    factor_cache_.solver = &S;
    factor_cache_.poses.resize(y.bodies.poses.size());
    std::copy(y.bodies.poses.begin(), y.bodies.poses.end(), factor_cache_.poses.begin());
    return true;
  }
  if (why) {
    const int g = S.groupOfRow(st.row);
    const int nj = static_cast<int>(model_.joints.size());
    const int np = static_cast<int>(prescribed_.size());
    std::ostringstream s;
    if (g < nj)
      s << model_.jointLabel(g) << ": " << constraintTypeName(model_.joints[g].constraint) << " row "
        << (st.row - S.rowBegin(g));
    else if (g < nj + np)
      s << model_.jointLabel(prescribed_[g - nj].joint) << ": prescribed motion of coordinate "
        << prescribed_[g - nj].coordinate + 1;
    else
      s << gears_[g - nj - np].name << ": gear row " << (st.row - S.rowBegin(g));
    s << " is redundant or conflicting with other constraints (singular J M⁻¹ Jᵀ: pivot " << st.pivot
      << " vs diagonal " << st.diagonal << ")";
    *why = s.str();
  }
  return false;
}

bool MultibodySystem::accelerations(double t, const State& y, Eigen::VectorXd* udot, Eigen::VectorXd* lambda,
                                    std::string* why) const {
  forces(t, y, true, &F_);
  if (!hasConstraints()) {
    // M⁻¹ F per body.
    udot->resize(n_);
    for (int i = 0; i < bodyCount(); ++i) {
      const RigidBody& body = model_.bodies[i];
      const int o = off_[i];
      if (rot_[i]) {
        udot->segment<3>(o) = body.inertia.ldlt().solve(F_.segment<3>(o));
      } else {
        udot->segment<3>(o) = F_.segment<3>(o) / body.mass;
        udot->segment<3>(o + 3) = body.inertia.ldlt().solve(F_.segment<3>(o + 3));
      }
    }
    if (lambda) lambda->resize(0);
    return true;
  }
  if (!factorConstraints(t, y, RowSet::kAll, why, nullptr, &c_)) return false;
  SchurSolver& S = all_;
  S.applyInverseMass(F_, y_);
  S.multiplyJ(y_, rhs_);
  rhs_ += c_;
  S.solve(rhs_, lam_);
  tmp_ = F_;
  S.addJTranspose(lam_, -1.0, tmp_);
  S.applyInverseMass(tmp_, *udot);
  if (lambda) *lambda = lam_;
  return true;
}

void MultibodySystem::velocity(double t, const State& y, Eigen::VectorXd* f) const {
  f->resize(2 * n_);
  for (int i = 0; i < bodyCount(); ++i) {
    const int o = off_[i];
    if (rot_[i]) {
      f->segment<3>(o) = y.bodies.velocities[i].omega;
    } else {
      f->segment<3>(o) = y.bodies.velocities[i].v;
      f->segment<3>(o + 3) = y.bodies.velocities[i].omega;
    }
  }
  if (!accelerations(t, y, &udot_, nullptr, nullptr)) {
    f->tail(n_).setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  f->tail(n_) = udot_;
}

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
    std::visit([&](const auto& con) { phi->segment(r, rows) = con.residual(pa, pb).tail(rows); }, j.constraint);
    r += rows;
  }
  for (const CoordinateRef& p : prescribed_)
    (*phi)[r++] = coordinate(y, p.joint, p.coordinate, nullptr, nullptr) -
                  (*drives_[p.joint][p.coordinate].prescribed)(t);
}

double MultibodySystem::constraintError(double t, const State& y) const {
  if (pos_groups_.empty()) return 0.0;
  positionResidual(t, y, &residual_);
  return residual_.lpNorm<Eigen::Infinity>();
}

double MultibodySystem::velocityConstraintError(double t, const State& y) const {
  if (!hasConstraints()) return 0.0;
  SchurSolver& S = all_;
  Eigen::VectorXd b(S.rows());  // fillGroups writes segments: size it first
  fillGroups(t, y, S, hasGears(), nullptr, &b, nullptr);
  Eigen::VectorXd Ju;
  S.multiplyJ(y.velocities(), Ju);
  return (Ju - b).lpNorm<Eigen::Infinity>();
}

void MultibodySystem::constraintJacobians(double t, const State& y, Eigen::VectorXd* phi,
                                          Eigen::VectorXd* b) const {
  // Position rows come first in all_, so Φ fills the head of the row range.
  if (phi) phi->resize(positionRowCount());
  if (b) b->resize(all_.rows());
  fillGroups(t, y, all_, hasGears(), phi, b, nullptr);
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
          for (std::size_t s = 0; s < C::kBodies; ++s) {
            const int body = gear.bodies[s];
            X[s] = body == kGround ? constraints::groundPose<double>() : y.bodies.poses[body];
            V[s] = body == kGround ? constraints::groundVelocity<double>() : y.bodies.velocities[body];
            if (body != kGround && rot_[body]) V[s].v.setZero();  // no δp columns (as multiplyJ)
          }
          const auto Bu = con.velocity(X, V);
          for (std::size_t k = 0; k < sel.size(); ++k) (*r)[r0 + static_cast<int>(k)] = Bu[sel[k]];
          r0 += static_cast<int>(sel.size());
        },
        gear.constraint);
  }
}

bool MultibodySystem::projectVelocities(double t, State* y, std::string* why) const {
  if (!hasConstraints()) return true;
  Eigen::VectorXd& b = b_;
  if (!factorConstraints(t, *y, RowSet::kAll, why, &b, nullptr)) return false;
  SchurSolver& S = all_;
  Eigen::VectorXd& u = u_;
  y->velocitiesInto(&u);
  S.multiplyJ(u, rhs_);
  rhs_ -= b;
  S.solve(rhs_, lam_);
  tmp_.setZero(n_);
  S.addJTranspose(lam_, 1.0, tmp_);
  S.applyInverseMass(tmp_, y_);
  u -= y_;
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
  Eigen::VectorXd& phi = phi_;
  positionResidual(t, *y, &phi);
  if (phi.lpNorm<Eigen::Infinity>() <= tolerance) return true;
  SchurSolver& S = schur(RowSet::kPosition);
  // A factorization of the position rows at nearby positions (the last
  // stage of the step just taken) serves the simplified Newton as well as
  // one at y: the iteration contracts by a factor of the order of the
  // distance between the two. It is kept while each iteration reduces max |Φ|
  // by kStaleContraction; otherwise y goes back to where that iteration
  // started and S is factored there.
  bool fresh = !(factor_cache_.valid && factor_cache_.solver == &S);
  if (fresh && !factorConstraints(t, *y, RowSet::kPosition, why)) return false;
  Eigen::VectorXd& d = projection_step_;
  d.setZero(2 * n_);
  double previous = phi.lpNorm<Eigen::Infinity>();
  int fresh_iterations = 0;
  for (int it = 1; it <= max_iterations; ++it) {
    if (!fresh) projection_backup_ = *y;
    // Δq = −M⁻¹ Jᵀ S⁻¹ Φ (simplified Newton: J and S held fixed).
    S.solve(phi, lam_);
    tmp_.setZero(n_);
    S.addJTranspose(lam_, -1.0, tmp_);
    S.applyInverseMass(tmp_, y_);
    d.head(n_) = y_;
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
      *y = projection_backup_;
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

std::vector<CoordinateElement> MultibodySystem::coordinateElements(const State& y) const {
  std::vector<CoordinateElement> out;
  for (std::size_t k = 0; k < model_.joints.size(); ++k)
    for (int i = 0; i < coordinateCount(static_cast<int>(k)); ++i) {
      const CoordinateDrive& d = drives_[k][i];
      if (d.stiffness == 0.0 && d.damping == 0.0) continue;
      CoordinateElement e;
      e.joint = static_cast<int>(k);
      e.coordinate = i;
      e.main = model_.joints[k].main;
      e.secondary = model_.joints[k].secondary;
      coordinate(y, e.joint, i, &e.J_main, &e.J_secondary);
      e.stiffness = d.stiffness;
      e.damping = d.damping;
      out.push_back(e);
    }
  return out;
}

// --- Observables ---------------------------------------------------------------

double MultibodySystem::energy(const State& y) const {
  double E = 0.0;
  for (int i = 0; i < bodyCount(); ++i) {
    const RigidBody& b = model_.bodies[i];
    const Eigen::Vector3d& w = y.bodies.velocities[i].omega;
    E += 0.5 * w.dot(b.inertia * w);
    if (!rot_[i]) {
      const Eigen::Vector3d& v = y.bodies.velocities[i].v;
      E += 0.5 * b.mass * v.squaredNorm() - b.mass * model_.gravity.dot(y.bodies.poses[i].p);
    }
  }
  for (std::size_t k = 0; k < model_.joints.size(); ++k)
    for (int i = 0; i < coordinateCount(static_cast<int>(k)); ++i) {
      const CoordinateDrive& d = drives_[k][i];
      if (d.stiffness == 0.0) continue;
      const double e = y.angles[2 * k + i] - d.rest_angle;
      E += 0.5 * d.stiffness * e * e;
    }
  return E;
}

Eigen::Vector3d MultibodySystem::angularMomentum(const State& y) const {
  Eigen::Vector3d L = Eigen::Vector3d::Zero();
  for (int i = 0; i < bodyCount(); ++i) {
    const RigidBody& b = model_.bodies[i];
    const auto& P = y.bodies.poses[i];
    const auto& V = y.bodies.velocities[i];
    L += P.R * (b.inertia * V.omega);
    if (!rot_[i]) L += P.p.cross(b.mass * V.v);
  }
  return L;
}

bool MultibodySystem::conservesAngularMomentum() const {
  // External moments about the origin come from gravity (unless every body
  // is rotation-only, held at its centre of mass), from the ground side of
  // joints and gears, and from the supports of rotation-only bodies whenever
  // a joint passes a force to them (its point rows are imposed). Joint
  // springs, dashpots, applied moments and prescribed motion between two
  // bodies act in equal and opposite pairs.
  bool all_rotation_only = true;
  for (int i = 0; i < bodyCount(); ++i) all_rotation_only = all_rotation_only && rot_[i];
  if (model_.gravity.squaredNorm() != 0.0 && !all_rotation_only) return false;
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const Joint& j = model_.joints[k];
    if (j.main == kGround || j.secondary == kGround) return false;
    if ((rot_[j.main] || rot_[j.secondary]) && skip_rows_[k] != 3) return false;
  }
  for (const Gear& g : gears_)
    for (int b : g.bodies)
      if (b == kGround || rot_[b]) return false;
  return true;
}

std::vector<JointOutput> MultibodySystem::jointOutputs(double t, const State& y) const {
  const int nj = static_cast<int>(model_.joints.size());
  std::vector<JointOutput> out(nj);
  bool any = false;
  for (int k = 0; k < nj; ++k) {
    out[k].coordinates = coordinateCount(k);
    any = any || out[k].coordinates > 0;
  }
  if (!any) return out;
  Eigen::VectorXd udot, lambda;
  std::string why;
  const bool solved = hasConstraints() && accelerations(t, y, &udot, &lambda, &why);
  SchurSolver& S = all_;
  // Prescribed row of (k, i), or −1.
  auto prescribedRow = [&](int k, int i) {
    int g = nj;
    for (const CoordinateRef& p : prescribed_) {
      if (p.joint == k && p.coordinate == i) return S.rowBegin(g);
      ++g;
    }
    return -1;
  };
  for (int k = 0; k < nj; ++k) {
    JointOutput& o = out[k];
    if (o.coordinates == 0) continue;
    const Joint& j = model_.joints[k];
    BodyPose<double> pa, pb;
    BodyVelocity<double> va, vb;
    poses(y, j.main, j.secondary, &pa, &pb, &va, &vb);
    // Generalized force (f world, τ body) of the joint on the main body (or on
    // the secondary when main is ground, negated at the end).
    const bool use_main = j.main != kGround;
    const BodyPose<double>& P = use_main ? pa : pb;
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    if (solved) g -= S.block(k, use_main ? 0 : 1).transpose() * lambda.segment(S.rowBegin(k), S.groupRows(k));
    std::array<Eigen::Vector3d, 2> axes;
    Eigen::Vector3d anchor;
    if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint)) {
      axes[0] = pa.R * rev->axis_main;
      anchor = pa.toWorld(rev->point.anchor_main);
    } else {
      const auto& uni = std::get<constraints::UniversalJoint<double>>(j.constraint);
      axes[0] = pa.R * uni.axis1_main;
      axes[1] = pb.R * uni.axis2_secondary;
      anchor = pa.toWorld(uni.point.anchor_main);
      o.condition = constraints::universalAngles(uni, pa, pb).condition;
    }
    for (int i = 0; i < o.coordinates; ++i) {
      Row6 Ja, Jb;
      o.phi[i] = coordinate(y, k, i, &Ja, &Jb);
      o.phidot[i] = Ja.tail<3>().dot(va.omega) + Jb.tail<3>().dot(vb.omega);
      const Row6& Jside = use_main ? Ja : Jb;
      const CoordinateDrive& d = drives_[k][i];
      double M = 0.0;
      if (d.hasForce()) {
        M = -d.stiffness * (o.phi[i] - d.rest_angle) - d.damping * o.phidot[i];
        if (d.moment) M += (*d.moment)(t);
      }
      const int pr = prescribedRow(k, i);
      if (solved && pr >= 0) M -= lambda[pr];
      g += Jside.transpose() * M;
    }
    const Eigen::Vector3d moment = P.R * g.tail<3>() - (anchor - P.p).cross(g.head<3>());
    for (int i = 0; i < o.coordinates; ++i) o.moment[i] = (use_main ? 1.0 : -1.0) * moment.dot(axes[i]);
  }
  return out;
}

}  // namespace multibody
}  // namespace lieflow
