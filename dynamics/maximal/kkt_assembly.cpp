#include "dynamics/maximal/kkt_assembly.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <utility>
#include <variant>

namespace lieflow {
namespace multibody {

namespace {

/// One-sided difference step of the geometric stiffness, in rad (and m):
/// ≈ √ε, so truncation and rounding errors are both ~1e-8 relative.
constexpr double kDifferenceStep = 1e-8;

}  // namespace

// --- Pattern ---------------------------------------------------------------------

bool KktAssembly::boundTo(const MultibodySystem& system) const {
  if (system_ != &system || n_ != system.dofs()) return false;
  const SchurSolver& S = system.schur(RowSet::kAll);
  if (static_cast<int>(rot_.size()) != system.bodyCount() || static_cast<int>(groups_.size()) != S.groupCount())
    return false;
  for (int b = 0; b < system.bodyCount(); ++b)
    if ((rot_[b] != 0) != system.rotationOnly(b)) return false;
  for (int g = 0; g < S.groupCount(); ++g)
    if (!(groups_[g] == S.group(g))) return false;
  return true;
}

bool KktAssembly::bind(const MultibodySystem& system) {
  if (boundTo(system)) return false;
  system_ = &system;
  const SchurSolver& S = system.schur(RowSet::kAll);
  const int nb = system.bodyCount(), ng = S.groupCount();
  n_ = system.dofs();
  m_ = S.rows();
  mp_ = system.positionRowCount();
  rot_.resize(nb);
  for (int b = 0; b < nb; ++b) rot_[b] = system.rotationOnly(b) ? 1 : 0;
  groups_.resize(ng);
  for (int g = 0; g < ng; ++g) groups_[g] = S.group(g);

  std::vector<Place> places;
  placeIndexOneBlocks(system, &places);
  placeStabilizedBlocks(system, &places);
  buildPattern(places, n_ + m_ + (stabilized_ ? mp_ : 0));
  Jr_.resize(nb);
  base_.resize(ng);
  colourBodies();
  return true;
}

void KktAssembly::placeIndexOneBlocks(const MultibodySystem& system, std::vector<Place>* out) {
  std::vector<Place>& places = *out;
  const SchurSolver& S = system.schur(RowSet::kAll);
  const int nb = system.bodyCount(), ng = S.groupCount();
  body_block_.resize(nb);
  for (int b = 0; b < nb; ++b) {
    body_block_[b] = static_cast<int>(places.size());
    places.push_back({system.dofBegin(b), system.dofBegin(b), dofsOf(b), dofsOf(b)});
  }
  std::map<std::pair<int, int>, int> pairs;
  pair_block_.assign(ng, {});
  j_block_.assign(ng, {});
  jt_block_.assign(ng, {});
  for (int g = 0; g < ng; ++g) {
    const RowGroup& G = groups_[g];
    for (int s = 0; s < kMaxGroupBodies; ++s) {
      pair_block_[g][s].fill(-1);
      j_block_[g][s] = jt_block_[g][s] = -1;
      const int b = G.bodies[s];
      if (b == kGround) continue;
      j_block_[g][s] = static_cast<int>(places.size());
      places.push_back({n_ + S.rowBegin(g), system.dofBegin(b), G.rows, dofsOf(b)});
      jt_block_[g][s] = static_cast<int>(places.size());
      places.push_back({system.dofBegin(b), n_ + S.rowBegin(g), dofsOf(b), G.rows});
      for (int s2 = 0; s2 < kMaxGroupBodies; ++s2) {
        const int b2 = G.bodies[s2];
        if (b2 == kGround) continue;
        if (b2 == b) {
          pair_block_[g][s][s2] = body_block_[b];
          continue;
        }
        const auto it = pairs.find({b, b2});
        if (it != pairs.end()) {
          pair_block_[g][s][s2] = it->second;
          continue;
        }
        const int k = static_cast<int>(places.size());
        pairs[{b, b2}] = k;
        pair_block_[g][s][s2] = k;
        places.push_back({system.dofBegin(b), system.dofBegin(b2), dofsOf(b), dofsOf(b2)});
      }
    }
  }
}

void KktAssembly::placeStabilizedBlocks(const MultibodySystem& system, std::vector<Place>* out) {
  std::vector<Place>& places = *out;
  const SchurSolver& S = system.schur(RowSet::kAll);
  const int nb = system.bodyCount(), ng = S.groupCount();
  // Stabilized: position rows below the velocity rows, ν columns right of
  // the λ columns (header comment); the blocks of the position rows (Φ_q T),
  // of the force rows in the ν columns (−(M + c_C C) M⁻¹ J̄ᵀ, per body) and
  // of the velocity rows in the ν columns (−J M⁻¹ J̄ᵀ, per pair of groups
  // sharing a body).
  pj_block_.assign(ng, {});
  fnu_block_.assign(ng, {});
  vnu_contributions_.clear();
  if (stabilized_) {
    start_.resize(ng);
    mid_.resize(ng);
    std::vector<std::vector<std::pair<int, int>>> all_of(nb), position_of(nb);  // (group, slot) per body
    for (int g = 0; g < ng; ++g) {
      pj_block_[g].fill(-1);
      fnu_block_[g].fill(-1);
      if (groups_[g].rows == 0) continue;
      const bool position = S.rowBegin(g) < mp_;
      for (int sl = 0; sl < kMaxGroupBodies; ++sl) {
        const int b = groups_[g].bodies[sl];
        if (b == kGround) continue;
        all_of[b].emplace_back(g, sl);
        if (!position) continue;
        position_of[b].emplace_back(g, sl);
        pj_block_[g][sl] = static_cast<int>(places.size());
        places.push_back({n_ + m_ + S.rowBegin(g), system.dofBegin(b), groups_[g].rows, dofsOf(b)});
        fnu_block_[g][sl] = static_cast<int>(places.size());
        places.push_back({system.dofBegin(b), n_ + m_ + S.rowBegin(g), dofsOf(b), groups_[g].rows});
      }
    }
    std::map<std::pair<int, int>, int> vnu;
    for (int b = 0; b < nb; ++b)
      for (const auto& k : all_of[b])
        for (const auto& l : position_of[b]) {
          auto it = vnu.find({k.first, l.first});
          if (it == vnu.end()) {
            it = vnu.emplace(std::make_pair(k.first, l.first), static_cast<int>(places.size())).first;
            places.push_back({n_ + S.rowBegin(k.first), n_ + m_ + S.rowBegin(l.first), groups_[k.first].rows,
                              groups_[l.first].rows});
          }
          vnu_contributions_.push_back({it->second, k.first, k.second, l.first, l.second});
        }
  }
}

void KktAssembly::buildPattern(const std::vector<Place>& places, int N) {
  std::vector<Eigen::Triplet<double, int>> t;
  for (const Place& p : places)
    for (int c = 0; c < p.cols; ++c)
      for (int r = 0; r < p.rows; ++r) t.emplace_back(p.row0 + r, p.col0 + c, 0.0);
  A_.resize(N, N);
  A_.setFromTriplets(t.begin(), t.end());  // no duplicates: the blocks are disjoint
  A_.makeCompressed();
  blocks_.resize(places.size());
  slots_.clear();
  for (std::size_t k = 0; k < places.size(); ++k) {
    const Place& p = places[k];
    blocks_[k] = Block{p.rows, p.cols, slots_.size()};
    for (int c = 0; c < p.cols; ++c) {
      const int col = p.col0 + c;
      const int* begin = A_.innerIndexPtr() + A_.outerIndexPtr()[col];
      const int* end = A_.innerIndexPtr() + A_.outerIndexPtr()[col + 1];
      for (int r = 0; r < p.rows; ++r)
        slots_.push_back(std::lower_bound(begin, end, p.row0 + r) - A_.innerIndexPtr());
    }
  }
}

void KktAssembly::colourBodies() {
  const int nb = static_cast<int>(rot_.size());
  // Greedy colouring of the graph "shares a row group" (geometricStiffness).
  colour_.assign(nb, -1);
  colours_ = 0;
  std::vector<std::vector<int>> neighbours(nb);
  for (const RowGroup& G : groups_)
    for (int p : G.bodies)
      for (int q : G.bodies)
        if (p != kGround && q != kGround && p != q) neighbours[p].push_back(q);
  std::vector<char> used;
  for (int b = 0; b < nb; ++b) {
    used.assign(colours_ + 1, 0);
    for (int q : neighbours[b])
      if (colour_[q] >= 0) used[colour_[q]] = 1;
    int c = 0;
    while (used[c]) ++c;
    colour_[b] = c;
    colours_ = std::max(colours_, c + 1);
  }
}

template <typename Derived>
void KktAssembly::addBlock(int k, const Eigen::MatrixBase<Derived>& value, int r0, int c0) {
  const Block& B = blocks_[k];
  double* v = A_.valuePtr();
  for (Eigen::Index c = 0; c < value.cols(); ++c)
    for (Eigen::Index r = 0; r < value.rows(); ++r)
      v[slots_[B.slot0 + (c0 + c) * B.rows + r0 + r]] += value(r, c);
}

// --- State -------------------------------------------------------------------------

void KktAssembly::advanceInto(const State& y, const Eigen::VectorXd& dq, const Eigen::VectorXd& u, State* out_ptr) {
  State& out = *out_ptr;
  out = y;
  const MultibodySystem& s = *y.system;
  for (int b = 0; b < s.bodyCount(); ++b) {
    const int o = s.dofBegin(b);
    BodyPose<double>& P = out.bodies.poses[b];
    if (s.rotationOnly(b)) {
      P.R = P.R * SO3d::exp(dq.segment<3>(o));
    } else {
      P.p += dq.segment<3>(o);
      P.R = P.R * SO3d::exp(dq.segment<3>(o + 3));
    }
  }
  out.setVelocities(u);
  // Joint angles: unwrapped near their first-order prediction φ + J_φ(y) dq,
  // not near y's values. A Newton iterate (the predictor at h ω ≫ 1, say) may
  // turn a joint by more than π in one step; the angle then follows the
  // increment along exp(s dq), s ∈ [0, 1] (exactly, for a turn about the
  // joint axis) instead of being wrapped back.
  auto rotation = [&](int b) -> Eigen::Vector3d {
    if (b == kGround) return Eigen::Vector3d::Zero();
    return dq.segment<3>(s.dofBegin(b) + (s.rotationOnly(b) ? 0 : 3));
  };
  auto pose = [&](int b) { return b == kGround ? constraints::groundPose<double>() : y.bodies.poses[b]; };
  const auto& joints = s.model().joints;
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const Joint& j = joints[k];
    const int nc = s.coordinateCount(static_cast<int>(k));
    if (nc == 0) continue;
    if (jointKind(j.constraint) == JointKind::kPrismatic) continue;  // x is set from the poses below
    const Eigen::Vector3d da = rotation(j.main), db = rotation(j.secondary);
    if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint)) {
      const auto J = constraints::revoluteAngleJacobians(*rev, pose(j.main), pose(j.secondary));
      out.angles[angleSlot(static_cast<int>(k), 0)] += J[0].tail<3>().dot(da) + J[1].tail<3>().dot(db);
    } else if (const auto* gim = std::get_if<constraints::GimbalJoint<double>>(&j.constraint)) {
      const auto J = constraints::gimbalAngleJacobians(*gim, pose(j.main), pose(j.secondary),
                                                       s.gimbalPrevious(y, static_cast<int>(k)));
      for (int i = 0; i < 3; ++i)
        out.angles[angleSlot(static_cast<int>(k), i)] += J[0].row(i).tail<3>().dot(da) + J[1].row(i).tail<3>().dot(db);
    } else {
      const auto J = constraints::universalAngleJacobians(*universalOf(j.constraint),
                                                          pose(j.main), pose(j.secondary));
      for (int i = 0; i < 2; ++i)
        out.angles[angleSlot(static_cast<int>(k), i)] += J[0].row(i).tail<3>().dot(da) + J[1].row(i).tail<3>().dot(db);
    }
  }
  s.rebaseAngles(&out);
}

bool KktAssembly::identical(const State& a, const State& b) {
  if (a.system != b.system || a.angles != b.angles || a.bodies.poses.size() != b.bodies.poses.size()) return false;
  for (std::size_t i = 0; i < a.bodies.poses.size(); ++i) {
    const auto& pa = a.bodies.poses[i];
    const auto& pb = b.bodies.poses[i];
    const auto& va = a.bodies.velocities[i];
    const auto& vb = b.bodies.velocities[i];
    if (pa.p != pb.p || pa.R.quaternion().coeffs() != pb.R.quaternion().coeffs() || va.v != vb.v ||
        va.omega != vb.omega)
      return false;
  }
  return true;
}

bool KktAssembly::accelerations(double t, const State& y, Eigen::VectorXd* udot, Eigen::VectorXd* lambda,
                                std::string* why) const {
  return system_->accelerations(t, y, udot, lambda, why);
}

void KktAssembly::startStep(double t, const State& y) {
  if (!stabilized_ || mp_ == 0) return;
  const MultibodySystem& s = *system_;
  s.constraintJacobians(t, y, nullptr, nullptr);
  const SchurSolver& S = s.schur(RowSet::kAll);
  for (int g = 0; g < static_cast<int>(groups_.size()); ++g) {
    if (S.rowBegin(g) >= mp_) continue;
    for (int sl = 0; sl < kMaxGroupBodies; ++sl) start_[g][sl] = mid_[g][sl] = S.block(g, sl);
  }
  mid_fixed_ = false;
}

void KktAssembly::addStartCorrection(const Eigen::VectorXd& nu, Eigen::VectorXd* dq) const {
  if (!stabilized_ || mp_ == 0) return;
  const MultibodySystem& s = *system_;
  const SchurSolver& S = s.schur(RowSet::kAll);
  for (int g = 0; g < static_cast<int>(groups_.size()); ++g) {
    const int rows = groups_[g].rows;
    if (S.rowBegin(g) >= mp_ || rows == 0) continue;
    const auto ng = nu.segment(S.rowBegin(g), rows);
    for (int sl = 0; sl < kMaxGroupBodies; ++sl) {
      const int b = groups_[g].bodies[sl];
      if (b == kGround) continue;
      const GroupBlock& J = mid_[g][sl];
      const int o = s.dofBegin(b);
      const RigidBody& body = s.model().bodies[b];
      if (rot_[b]) {
        dq->segment<3>(o) += body.inertia.inverse() * (J.rightCols<3>().transpose() * ng);
      } else {
        dq->segment<3>(o) += (J.leftCols<3>().transpose() * ng) / body.mass;
        dq->segment<3>(o + 3) += body.inertia.inverse() * (J.rightCols<3>().transpose() * ng);
      }
    }
  }
}

// --- Residual --------------------------------------------------------------------------

double KktAssembly::residual(double t, const State& y, const Eigen::VectorXd& udot, const Eigen::VectorXd& lambda,
                             Eigen::VectorXd* r, Eigen::VectorXd* c) {
  const MultibodySystem& s = *system_;
  t_ = t;
  s.forces(t, y, true, &F_);
  Mu_.resize(n_);
  for (int b = 0; b < s.bodyCount(); ++b) {
    const RigidBody& body = s.model().bodies[b];
    const int o = s.dofBegin(b);
    if (rot_[b]) {
      Mu_.segment<3>(o).noalias() = body.inertia * udot.segment<3>(o);
    } else {
      Mu_.segment<3>(o) = body.mass * udot.segment<3>(o);
      Mu_.segment<3>(o + 3).noalias() = body.inertia * udot.segment<3>(o + 3);
    }
  }
  JTl_.setZero(n_);
  c->resize(stabilized_ ? mp_ + m_ : m_);
  if (m_ > 0) {
    s.constraintJacobians(t, y, &phi_, &b_);
    const SchurSolver& S = s.schur(RowSet::kAll);
    S.addJTranspose(lambda, 1.0, JTl_);
    c->head(mp_) = phi_;
    if (stabilized_) {
      y.velocitiesInto(&u_);
      S.multiplyJ(u_, Ju_);
      c->tail(m_) = Ju_ - b_;
    } else if (m_ > mp_) {
      y.velocitiesInto(&u_);
      S.multiplyJ(u_, Ju_);
      c->tail(m_ - mp_) = Ju_.tail(m_ - mp_) - b_.tail(m_ - mp_);
    }
  }
  *r = Mu_ - F_ + JTl_;
  return std::max({Mu_.lpNorm<Eigen::Infinity>(), F_.lpNorm<Eigen::Infinity>(), JTl_.lpNorm<Eigen::Infinity>()});
}

// --- Iteration matrix ----------------------------------------------------------------------

const Eigen::SparseMatrix<double>& KktAssembly::matrix(const State& y, const Eigen::VectorXd& dq,
                                                       double damping_factor, double stiffness_factor,
                                                       const Eigen::VectorXd& lambda) {
  const MultibodySystem& s = *system_;
  std::fill(A_.valuePtr(), A_.valuePtr() + A_.nonZeros(), 0.0);
  const int nb = s.bodyCount();
  // Per body: M + c_C (ω^ J − (Jω)^), and T's rotation block Jr(hΔθ).
  for (int b = 0; b < nb; ++b) {
    const RigidBody& body = s.model().bodies[b];
    const int r0 = rotationBegin(b);
    const Eigen::Vector3d& w = y.bodies.velocities[b].omega;
    if (!rot_[b]) addBlock(body_block_[b], (body.mass * Eigen::Matrix3d::Identity()).eval());
    const Eigen::Matrix3d C = SO3d::hat(w) * body.inertia - SO3d::hat(body.inertia * w);
    addBlock(body_block_[b], (body.inertia + damping_factor * C).eval(), r0, r0);
    Jr_[b] = SO3d::Jr(dq.segment<3>(s.dofBegin(b) + r0));
  }
  // Springs k J_φᵀ J_φ T and dashpots c J_φᵀ J_φ, T = diag(I, Jr) (J_φ has
  // translation columns for a prismatic joint only; a rotation-only body
  // takes the rotation columns).
  s.coordinateElementsInto(y, &elements_);
  for (const CoordinateElement& e : elements_) {
    const std::array<int, 2> body{{e.main, e.secondary}};
    const std::array<Eigen::Matrix<double, 1, 6>, 2> j{{e.J_main, e.J_secondary}};
    for (int p = 0; p < 2; ++p) {
      if (body[p] == kGround) continue;
      for (int q = 0; q < 2; ++q) {
        if (body[q] == kGround) continue;
        Eigen::Matrix<double, 1, 6> jT = j[q];
        jT.tail<3>() = j[q].tail<3>() * Jr_[body[q]];
        const Eigen::Matrix<double, 1, 6> row = damping_factor * e.damping * j[q] + stiffness_factor * e.stiffness * jT;
        const Eigen::Matrix<double, 6, 6> K = j[p].transpose() * row;
        const int cp = rot_[body[p]] ? 3 : 0, cq = rot_[body[q]] ? 3 : 0;
        addBlock(pair_block_[e.joint][p][q], K.block(cp, cq, 6 - cp, 6 - cq));
      }
    }
  }
  // Constraint rows J T and columns Jᵀ.
  if (m_ > 0) {
    const SchurSolver& S = s.schur(RowSet::kAll);
    for (int g = 0; g < static_cast<int>(groups_.size()); ++g)
      for (int sl = 0; sl < kMaxGroupBodies; ++sl) {
        const int b = groups_[g].bodies[sl];
        if (b == kGround) continue;
        const GroupBlock& J = S.block(g, sl);
        const int r0 = rotationBegin(b);
        if (!rot_[b]) {
          addBlock(j_block_[g][sl], J.leftCols<3>());
          addBlock(jt_block_[g][sl], J.leftCols<3>().transpose());
        }
        // Index 3: the rows are Φ_q T (gear rows too: their ∂(B u)/∂ΔΔ =
        // γ' B is taken as B T, which costs iterations, not accuracy).
        // Stabilized: the velocity rows J (∂(J u)/∂δq T / γ' below).
        if (stabilized_) {
          addBlock(j_block_[g][sl], J.rightCols<3>(), 0, r0);
          if (pj_block_[g][sl] >= 0) {  // Φ_q T; −(M + c_C C) M⁻¹ J̄ᵀ
            // J̄ = ½ (J(q_n) + J(q̃_{n+1})) at the step's first iterate, kept
            // for the step: the (nearly) symmetric correction (header comment).
            if (!mid_fixed_) mid_[g][sl] = 0.5 * (start_[g][sl] + J);
            const GroupBlock& Jn = mid_[g][sl];
            const RigidBody& body = s.model().bodies[b];
            const Eigen::Vector3d& w = y.bodies.velocities[b].omega;
            const Eigen::Matrix3d C = SO3d::hat(w) * body.inertia - SO3d::hat(body.inertia * w);
            if (!rot_[b]) {
              addBlock(pj_block_[g][sl], J.leftCols<3>());
              addBlock(fnu_block_[g][sl], (-Jn.leftCols<3>().transpose()).eval());
            }
            addBlock(pj_block_[g][sl], (J.rightCols<3>() * Jr_[b]).eval(), 0, r0);
            addBlock(fnu_block_[g][sl],
                     (-(body.inertia + damping_factor * C) * body.inertia.inverse() * Jn.rightCols<3>().transpose())
                         .eval(),
                     r0, 0);
          }
        } else {
          addBlock(j_block_[g][sl], (J.rightCols<3>() * Jr_[b]).eval(), 0, r0);
        }
        addBlock(jt_block_[g][sl], J.rightCols<3>().transpose(), r0, 0);
      }
    mid_fixed_ = true;
    // Stabilized: −J M⁻¹ J̄ᵀ of the velocity rows in the ν columns.
    for (const NuContribution& c : vnu_contributions_) {
      const int b = groups_[c.g].bodies[c.s];
      const RigidBody& body = s.model().bodies[b];
      const GroupBlock& J = S.block(c.g, c.s);
      const GroupBlock& Jn = mid_[c.g2][c.s2];
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxGroupRows, kMaxGroupRows> v =
          -(J.rightCols<3>() * body.inertia.inverse()) * Jn.rightCols<3>().transpose();
      if (!rot_[b]) v.noalias() -= (J.leftCols<3>() * Jn.leftCols<3>().transpose()) / body.mass;
      addBlock(c.block, v);
    }
    // Stabilized: the velocity rows' ∂(J u)/∂δq T too (scaled by 1/γ' =
    // c_K / c_C), from the same differences.
    if (options_.geometric_stiffness)
      geometricStiffness(y, lambda, stiffness_factor, stabilized_ ? stiffness_factor / damping_factor : 0.0, Jr_);
  }
  return A_;
}

void KktAssembly::geometricStiffness(const State& y, const Eigen::VectorXd& lambda, double factor,
                                     double velocity_factor, const std::vector<Eigen::Matrix3d>& Jr) {
  // K_λ = ∂(Jᵀλ)/∂δq by one-sided differences of the blocks the system fills
  // itself (MultibodySystem::constraintJacobians), so the rows are exactly
  // the imposed ones. All bodies of one colour are perturbed at once in one
  // coordinate j: no row group holds two bodies of one colour, so the change
  // of group g's blocks is the derivative with respect to its body of that
  // colour. Column j of the block (b₂, b) is (J_{g,b₂}(q ⊕ ε e_j) − J_{g,b₂}(q))ᵀ λ_g / ε;
  // times c_K and times T (row j of diag(I, Jr_b)) it is added as a rank-1 term.
  const MultibodySystem& s = *system_;
  SchurSolver& S = s.schur(RowSet::kAll);
  const int ng = static_cast<int>(groups_.size());
  for (int g = 0; g < ng; ++g)
    for (int sl = 0; sl < kMaxGroupBodies; ++sl) base_[g][sl] = S.block(g, sl);
  State& yp = perturbed_;
  yp = y;
  const int j0 = s.jacobiansDependOnPositions() ? 0 : 3;
  Eigen::Matrix<double, 1, 6> trow;
  for (int k = 0; k < colours_; ++k)
    for (int j = j0; j < 6; ++j) {
      bool any = false;
      for (int b = 0; b < s.bodyCount(); ++b) {
        yp.bodies.poses[b] = y.bodies.poses[b];
        if (colour_[b] != k || (rot_[b] && j < 3)) continue;
        yp.bodies.poses[b] = y.bodies.poses[b].rplus(kDifferenceStep * Eigen::Matrix<double, 6, 1>::Unit(j));
        any = true;
      }
      if (!any) continue;
      s.constraintJacobians(t_, yp, nullptr, nullptr);
      for (int g = 0; g < ng; ++g) {
        const RowGroup& G = groups_[g];
        if (G.rows == 0) continue;
        const auto lg = lambda.segment(S.rowBegin(g), G.rows);
        for (int sl = 0; sl < kMaxGroupBodies; ++sl) {
          const int b = G.bodies[sl];
          if (b == kGround || colour_[b] != k || (rot_[b] && j < 3)) continue;
          // Row j of T_b over b's dofs.
          trow.setZero();
          if (j < 3) trow[j] = 1.0;
          else trow.tail<3>() = Jr[b].row(j - 3);
          const int c6 = rot_[b] ? 3 : 0;
          GroupRows dJu = GroupRows::Zero(G.rows);  // ∂(J u)/∂q_{b,j}
          for (int s2 = 0; s2 < kMaxGroupBodies; ++s2) {
            const int b2 = G.bodies[s2];
            if (b2 == kGround) continue;
            const GroupBlock dJ = S.block(g, s2) - base_[g][s2];
            const Eigen::Matrix<double, 6, 1> col = dJ.transpose() * lg * (factor / kDifferenceStep);
            const Eigen::Matrix<double, 6, 6> K = col * trow;
            const int r6 = rot_[b2] ? 3 : 0;
            addBlock(pair_block_[g][s2][sl], K.block(r6, c6, 6 - r6, 6 - c6));
            if (velocity_factor != 0.0) {
              const BodyVelocity<double>& v = y.bodies.velocities[b2];
              dJu.noalias() += dJ.rightCols<3>() * v.omega;
              if (!rot_[b2]) dJu.noalias() += dJ.leftCols<3>() * v.v;
            }
          }
          if (velocity_factor != 0.0) {
            const Eigen::Matrix<double, Eigen::Dynamic, 6, 0, kMaxGroupRows, 6> V =
                dJu * trow * (velocity_factor / kDifferenceStep);
            addBlock(j_block_[g][sl], V.rightCols(6 - c6));
          }
        }
      }
    }
  // Leave J(y) in the solver, as residual() did.
  for (int g = 0; g < ng; ++g)
    for (int sl = 0; sl < kMaxGroupBodies; ++sl) S.block(g, sl) = base_[g][sl];
}

}  // namespace multibody
}  // namespace lieflow
