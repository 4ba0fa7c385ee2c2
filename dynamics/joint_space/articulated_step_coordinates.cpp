// ArticulatedSystem: the coordinates of lgvi's step beyond the joint
// angles (integrators/joint_space_variational.hpp; articulated_system.hpp
// states the equations): the rotations' discrete Lagrangian on SO(3), each
// free tree's centre of mass as its translation, and the constraint rows'
// multipliers (coupling rows, loops, gear rows: RATTLE).
#include <algorithm>
#include <cmath>
#include <limits>

#include "dynamics/joint_space/articulated_system.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace articulated {

namespace {

/// A loop's row |Φ| within this many ulps of the bodies' farthest coordinate
/// (at least 1 m) is closed to rounding (projectIncrement).
constexpr double kLoopRoundingUlps = 64.0;

}  // namespace

// ---- rotations on SO(3) -------------------------------------------------

void ArticulatedSystem::advance(const State& y, const Eigen::VectorXd& v, double s, State* out) const {
  const int nq = y.scalarCount();
  out->q = y.q + s * v.head(nq);
  out->N.resize(y.N.size());
  for (std::size_t k = 0; k < y.N.size(); ++k)
    out->N[k] = y.N[k] * SO3d::exp(s * v.segment<3>(nq + 3 * static_cast<int>(k)));
}

bool ArticulatedSystem::sameConfiguration(const State& a, const State& b) {
  if (a.q.size() != b.q.size() || a.N.size() != b.N.size() || a.q != b.q) return false;
  for (std::size_t k = 0; k < a.N.size(); ++k)
    if (a.N[k].quaternion().coeffs() != b.N[k].quaternion().coeffs()) return false;
  return true;
}

void ArticulatedSystem::rotationStartTerms(const Eigen::VectorXd& v, double h, Eigen::VectorXd* Mv, Eigen::VectorXd* dT,
                                    RotationTerms* terms) const {
  const int nq = model_.scalar_coordinates;
  terms->xi.resize(model_.rotations);
  terms->pi.resize(model_.rotations);
  terms->delta.resize(model_.rotations);
  for (int k = 0; k < model_.rotations; ++k) {
    const int o = nq + 3 * k;
    const Eigen::Vector3d xi = h * v.segment<3>(o);
    const Eigen::Matrix3d JlInv = SO3d::JlInv(xi);
    const Eigen::Matrix3d B = SO3d::exp(-0.5 * xi).matrix() - 0.5 * SO3d::Jr(0.5 * xi) * JlInv;
    terms->xi[k] = xi;
    terms->pi[k] = Mv->segment<3>(o);
    terms->delta[k] = dT->segment<3>(o);
    Mv->segment<3>(o).noalias() = JlInv.transpose() * terms->pi[k];
    dT->segment<3>(o).noalias() = 2.0 * (B.transpose() * terms->delta[k]);
  }
}

void ArticulatedSystem::rotationEndMomenta(double h, const RotationTerms& terms, const Eigen::VectorXd& b,
                                      Eigen::VectorXd* p) const {
  const int nq = model_.scalar_coordinates;
  for (int k = 0; k < model_.rotations; ++k) {
    const int o = nq + 3 * k;
    // D₂L_d + D₁L_d = (Jr⁻¹ − Jl⁻¹)(ξ)ᵀ π + h (A + B)ᵀ δ, Jr⁻¹ − Jl⁻¹ = [ξ]×,
    // A + B = exp(−ξ/2) + ½ Jr(ξ/2) [ξ]×.
    const Eigen::Vector3d& xi = terms.xi[k];
    const Eigen::Matrix3d AB = SO3d::exp(-0.5 * xi).matrix() + 0.5 * SO3d::Jr(0.5 * xi) * hat(xi);
    p->segment<3>(o) = b.segment<3>(o) + cross3(terms.pi[k], xi) + h * (AB.transpose() * terms.delta[k]);
  }
}

// ---- free trees: the translation is the tree's centre of mass ----------

void ArticulatedSystem::centreFreeTrees(const Frames& f, const Eigen::VectorXd& v, bool state_rates) const {
  if (free_root_body_.empty()) return;
  // The trees' momenta with v_c = 0, P₀ = Σ m v_c; each tree's v_z (given,
  // or v_c + P₀/M_tree from the state's v_c); then the uniform motion
  // −P₀/M_tree added to every body of the tree, which brings its momentum
  // to zero: the twists (0, u), the momenta (c × m u, m u).
  data_.tree_vz.resize(model_.rotations);
  data_.tree_shift.assign(model_.rotations, Eigen::Vector3d::Zero());
  const int n = bodyCount();
  for (int i = 0; i < n; ++i)
    if (free_tree_[i] >= 0) data_.tree_shift[free_tree_[i]] += data_.accumulated[i].tail<3>();
  for (int r : free_root_body_) {
    const ArticulatedBody& b = model_.bodies[r];
    const Eigen::Vector3d rest = data_.tree_shift[b.rotation] / free_tree_mass_[b.rotation];
    data_.tree_vz[b.rotation] = state_rates ? Eigen::Vector3d(v.segment<3>(b.u_begin) + rest)
                                            : Eigen::Vector3d(v.segment<3>(b.u_begin));
    data_.tree_shift[b.rotation] = -rest;
  }
  for (int i = 0; i < n; ++i) {
    if (free_tree_[i] < 0) continue;
    const Eigen::Vector3d& u = data_.tree_shift[free_tree_[i]];
    const Eigen::Vector3d mu = model_.bodies[i].mass * u;
    data_.accumulated[i].head<3>() += cross3(f.bodies[i].c, mu);
    data_.accumulated[i].tail<3>() += mu;
    data_.twist[i].tail<3>() += u;
    if (model_.bodies[i].kind != JointKind::kFree) data_.before[i].tail<3>() += u;
  }
}

void ArticulatedSystem::placeFreeRoots(const Frames& start, const Frames& end, const State& y0,
                                       const Eigen::VectorXd& v, double h, State* y1) const {
  // z₁ = z₀ + h v_z, the root at z − (its tree's centre from it).
  for (int r : free_root_body_) {
    const ArticulatedBody& b = model_.bodies[r];
    y1->q.segment<3>(b.q_begin) = y0.q.segment<3>(b.q_begin) + start.root_offset[b.rotation] +
                                  h * v.segment<3>(b.u_begin) - end.root_offset[b.rotation];
  }
}

// ---- closures: RATTLE's multipliers --------------------------------------

void ArticulatedSystem::projectIncrement(const Frames& start, const Frames& mid, const State& y,
                                         const Eigen::VectorXd& v, double h, Eigen::VectorXd* dv,
                                         Eigen::VectorXd* r) const {
  if (coupling_G_.size() != 0) {
    // Coupling rows: G (v + dv) = 0.
    data_.coupling_g.noalias() = coupling_G_ * v;
    data_.coupling_g.noalias() += coupling_G_ * *dv;
    data_.coupling_lambda.noalias() = start.rows_Ainv * data_.coupling_g;
    dv->noalias() -= start.rows_Y * data_.coupling_lambda;
    r->noalias() -= coupling_G_.transpose() * data_.coupling_lambda;
    return;
  }
  if (!loopRows()) return;
  // G₀ dv, plus Φ(q₀ ⊕ h v)/h on a loop's rows and B(q_m) v on gear rows.
  data_.coupling_g.noalias() = start.rows_G * *dv;
  if (has_position_rows_) {
    advance(y, v, h, &loop_end_);
    frames(0.0, loop_end_, false, &loop_frames_);
    loadFramePoses(loop_frames_);
    closureTerms(ClosureLevel::kPosition);
    // Φ at the rounding of the positions is met: kept, its noise over h would
    // set the iteration's floor, which near a turning point (v → 0, the
    // bound relative to v with it) it could not reach.
    double reach = 1.0;
    for (const Frame& fr : loop_frames_.bodies) reach = std::max(reach, fr.c.cwiseAbs().maxCoeff());
    const double met = kLoopRoundingUlps * std::numeric_limits<double>::epsilon() * reach;
    for (int k = 0; k < model_.closure_rows; ++k)
      if (position_rows_[k] != 0.0 && std::abs(data_.closure_r[k]) > met) data_.coupling_g[k] += data_.closure_r[k] / h;
  }
  if (has_velocity_rows_) {
    loadFramePoses(mid);
    closureTerms(ClosureLevel::kJacobian);
    data_.closure_rhs.noalias() = data_.closure_G * v;
    data_.coupling_g.array() += (1.0 - position_rows_.array()) * data_.closure_rhs.array();
  }
  data_.loop_lambda.noalias() = start.rows_Ainv * data_.coupling_g;
  dv->noalias() -= start.rows_Y * data_.loop_lambda;
  r->noalias() -= start.rows_G.transpose() * data_.loop_lambda;
}

void ArticulatedSystem::constraintImpulse(const Frames& start, Eigen::VectorXd* b) const {
  if (!loopRows()) return;
  b->noalias() -= start.rows_G.transpose() * data_.loop_lambda;
}

void ArticulatedSystem::rates(const Frames& f, Eigen::VectorXd* p, Eigen::VectorXd* u) const {
  if (hasClosures()) {
    // μ with G M⁻¹ (p + Gᵀμ) = 0: −(G Y)⁻¹ G M⁻¹ p (G at f: q₁'s).
    const Eigen::MatrixXd& G = coupling_G_.size() != 0 ? coupling_G_ : f.rows_G;
    solveStepMass(f, *p, false, &data_.coupling_x);
    data_.coupling_g.noalias() = G * data_.coupling_x;
    data_.coupling_lambda.noalias() = f.rows_Ainv * data_.coupling_g;
    p->noalias() -= G.transpose() * data_.coupling_lambda;
  }
  solveStepMass(f, *p, true, u);
}

}  // namespace articulated
}  // namespace lieflow
