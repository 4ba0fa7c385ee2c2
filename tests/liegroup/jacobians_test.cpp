/// \file
/// Every closed-form Jacobian of SO3d and SE3d against two independent
/// references:
///  * central finite differences of the right-perturbation definition
///    J = ∂/∂δ [f(x ⊕ δ) ⊖ f(x)] (step 1e-6; see test_helpers.hpp), and
///  * forward-mode automatic differentiation with ceres::Jet, differentiating
///    the same operation on Jet-valued inputs (group outputs are read through
///    their matrix, vee(M₀⁻¹ ∂M), not through log),
/// both to a relative Frobenius discrepancy ≤ 1e-7, at θ = 0 exactly, near
/// the identity (1e-9, 1e-5), at random points, near π (π − 1e-5, π − 1e-9)
/// and at the series/closed-form switches of detail/series.hpp. Near π the
/// finite differences of log-based maps follow the continuous branch of log
/// (logNear), since X exp(±hδ) may cross the seam at π.
#include <functional>
#include <iomanip>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "test_helpers.hpp"

namespace lieflow {
namespace test {
namespace {

constexpr double kTolerance = 1e-7;
constexpr int kSamplesPerBand = 2000;
constexpr int kSamplesPerThresholdBand = 100;

/// The worst discrepancies of one Jacobian over all samples.
struct Discrepancy {
  MaxTracker fd, jet;
};

using Table = std::map<std::string, Discrepancy>;

void printTable(const std::string& group, const Table& table) {
  std::cout << "[ measured ] " << group << " Jacobians, worst relative discrepancy (FD | Jet):\n";
  for (const auto& [name, d] : table) {
    std::cout << "             " << std::left << std::setw(22) << name << std::scientific
              << std::setprecision(2) << d.fd.value << " | " << d.jet.value << "   (FD worst at "
              << d.fd.where << "; Jet worst at " << (d.jet.where.empty() ? "-, exact" : d.jet.where)
              << ")\n";
    ::testing::Test::RecordProperty(group + "." + name + ".fd", d.fd.value);
    ::testing::Test::RecordProperty(group + "." + name + ".jet", d.jet.value);
  }
  std::cout << std::defaultfloat << std::flush;
}

void expectWithinTolerance(const std::string& group, const Table& table) {
  for (const auto& [name, d] : table) {
    EXPECT_LE(d.fd.value, kTolerance) << group << "::" << name << " vs finite differences, at "
                                      << d.fd.where;
#ifdef LIEFLOW_HAVE_CERES
    EXPECT_LE(d.jet.value, kTolerance) << group << "::" << name << " vs ceres::Jet, at " << d.jet.where;
#endif
  }
}

/// All Jacobians of GroupT<double> at one sample point of a band.
template <template <typename> class GroupT>
struct JacobianChecks {
  using G = GroupT<double>;
  static constexpr int n = G::DoF;
  using Tan = Eigen::Matrix<double, n, 1>;
  using VecX = Eigen::VectorXd;
  using MatX = Eigen::MatrixXd;
#ifdef LIEFLOW_HAVE_CERES
  using GJ = GroupT<Jet>;
  using TanJ = Eigen::Matrix<Jet, n, 1>;
  static TanJ deltaJ() { return seed<n>(Tan::Zero()); }
  static GJ expDeltaJ() { return GJ::exp(deltaJ()); }
#endif

  /// Central differences of g: ℝᵐ → ℝᵏ at 0 (m = DoF unless told).
  template <int m = n, typename F>
  static MatX fd(F g) {
    return centralDifference([&](const VecX& d) -> VecX { return g(Eigen::Matrix<double, m, 1>(d)); }, m);
  }

  Table& table;
  std::string where;

  void record(const std::string& name, const MatX& closed, const MatX& fd_ref, const MatX& jet_ref) {
    fd_ref.allFinite() ? table[name].fd.update(relativeError(closed, fd_ref), where)
                       : table[name].fd.update(NAN, where + " (non-finite FD)");
#ifdef LIEFLOW_HAVE_CERES
    jet_ref.allFinite() ? table[name].jet.update(relativeError(closed, jet_ref), where)
                        : table[name].jet.update(NAN, where + " (non-finite Jet derivative)");
#else
    (void)jet_ref;
#endif
  }

  void run(const AngleBand& band, Rng& rng) {
    const Tan w = sampleTangent<G>(band, rng);
    const G X = G::exp(w);
    const G Y = G::exp(sampleTangent<G>(band, rng));
    const Tan tau = sampleTangent<G>(band, rng);
    const G Xr = G::exp(sampleTangent<G>(AngleBand{"random", -1.0}, rng));  // base of ⊕ / ⊖
    const Eigen::Vector3d p = std::uniform_real_distribution<double>(0.5, 2.0)(rng) * randomUnit(rng);
    std::ostringstream at;
    at << band.name << ", w = [" << w.transpose() << "]";
    where = at.str();
#ifdef LIEFLOW_HAVE_CERES
    const GJ XJ = X.template cast<Jet>(), YJ = Y.template cast<Jet>(), XrJ = Xr.template cast<Jet>();
    const Vector3<Jet> pJ = constant<3>(p);
// The Jet reference: the expression's Jet Jacobian, or nothing without Ceres.
#define LIEFLOW_JET(...) [&]() -> MatX { return __VA_ARGS__; }()
#else
#define LIEFLOW_JET(...) MatX()
#endif

    // exp: exp(w + δ) ≈ exp(w) exp(Jr δ) ≈ exp(Jl δ) exp(w).
    const MatX Jr_fd = fd([&](const Tan& d) { return (X.inverse() * G::exp(w + d)).log(); });
    const MatX Jr_jet = LIEFLOW_JET(jetRightJacobianOfGroup(GJ::exp(seed<n>(w))));
    record("Jr", G::Jr(w), Jr_fd, Jr_jet);
    record("expJacobian", G::expJacobian(w), Jr_fd, Jr_jet);
    record("Jl", G::Jl(w),
           fd([&](const Tan& d) { return (G::exp(w + d) * X.inverse()).log(); }),
           LIEFLOW_JET(jetLeftJacobianOfGroup(GJ::exp(seed<n>(w)))));

    // log: log(exp(w) exp(δ)) ≈ w + Jr⁻¹ δ, log(exp(δ) exp(w)) ≈ w + Jl⁻¹ δ.
    record("JrInv", G::JrInv(w),
           fd([&](const Tan& d) { return logNear(X * G::exp(d), w); }),
           LIEFLOW_JET(jetJacobian((GJ::exp(constant<n>(w)) * expDeltaJ()).log(), n)));
    record("JlInv", G::JlInv(w),
           fd([&](const Tan& d) { return logNear(G::exp(d) * X, w); }),
           LIEFLOW_JET(jetJacobian((expDeltaJ() * GJ::exp(constant<n>(w))).log(), n)));
    const Tan logX = X.log();
    record("logJacobian", X.logJacobian(),
           fd([&](const Tan& d) { return logNear(X * G::exp(d), logX); }),
           LIEFLOW_JET(jetJacobian((XJ * expDeltaJ()).log(), n)));

    // inverse, compose.
    record("inverseJacobian", X.inverseJacobian(),
           fd([&](const Tan& d) { return (X * G::exp(d)).inverse().rminus(X.inverse()); }),
           LIEFLOW_JET(jetRightJacobianOfGroup((XJ * expDeltaJ()).inverse())));
    const G XY = X * Y;
    record("composeJacobianLhs", X.composeJacobianLhs(Y),
           fd([&](const Tan& d) { return (X * G::exp(d) * Y).rminus(XY); }),
           LIEFLOW_JET(jetRightJacobianOfGroup(XJ * expDeltaJ() * YJ)));
    record("composeJacobianRhs", G::composeJacobianRhs(),
           fd([&](const Tan& d) { return (X * (Y * G::exp(d))).rminus(XY); }),
           LIEFLOW_JET(jetRightJacobianOfGroup(XJ * (YJ * expDeltaJ()))));

    // action on a point.
    const Eigen::Vector3d Xp = X * p;
    record("actJacobianGroup", X.actJacobianGroup(p),
           fd([&](const Tan& d) { return VecX((X * G::exp(d)) * p - Xp); }),
           LIEFLOW_JET(jetJacobian((XJ * expDeltaJ()) * pJ, n)));
    record("actJacobianPoint", X.actJacobianPoint(p),
           fd<3>([&](const Eigen::Vector3d& d) { return VecX(X * (p + d) - Xp); }),
           LIEFLOW_JET(jetJacobian(XJ * seed<3>(p), 3)));

    // ⊕: (Xr ⊕ τ) w.r.t. Xr and τ.
    const G Xr_tau = Xr.rplus(tau);
    record("rplusJacobianLhs", G::rplusJacobianLhs(tau),
           fd([&](const Tan& d) { return (Xr * G::exp(d)).rplus(tau).rminus(Xr_tau); }),
           LIEFLOW_JET(jetRightJacobianOfGroup((XrJ * expDeltaJ()).rplus(constant<n>(tau)))));
    record("rplusJacobianRhs", G::rplusJacobianRhs(tau),
           fd([&](const Tan& d) { return Xr.rplus(tau + d).rminus(Xr_tau); }),
           LIEFLOW_JET(jetRightJacobianOfGroup(XrJ.rplus(seed<n>(tau)))));

    // ⊖: (Y ⊖ Xr) with Y = Xr ⊕ τ, so Y ⊖ Xr = τ (near π in the π bands).
    const G& Yt = Xr_tau;
    const Tan Yt_minus_Xr = Yt.rminus(Xr);
    record("rminusJacobianLhs", Yt.rminusJacobianLhs(Xr),
           fd([&](const Tan& d) { return logNear(Xr.inverse() * (Yt * G::exp(d)), Yt_minus_Xr); }),
           LIEFLOW_JET(jetJacobian((Yt.template cast<Jet>() * expDeltaJ()).rminus(XrJ), n)));
    record("rminusJacobianRhs", Yt.rminusJacobianRhs(Xr),
           fd([&](const Tan& d) { return logNear((Xr * G::exp(d)).inverse() * Yt, Yt_minus_Xr); }),
           LIEFLOW_JET(jetJacobian(Yt.template cast<Jet>().rminus(XrJ * expDeltaJ()), n)));
  }
#undef LIEFLOW_JET
};

template <template <typename> class GroupT>
void checkAllJacobians(const std::string& group, std::uint64_t seed_value) {
  Table table;
  JacobianChecks<GroupT> checks{table, ""};
  Rng rng(seed_value);
  for (const AngleBand& band : standardBands()) {
    const int count = band.theta == 0.0 ? 1 : kSamplesPerBand;
    for (int i = 0; i < count; ++i) checks.run(band, rng);
  }
  for (const AngleBand& band : thresholdBands())
    for (int i = 0; i < kSamplesPerThresholdBand; ++i) checks.run(band, rng);
  printTable(group, table);
  expectWithinTolerance(group, table);
}

TEST(LieJacobiansSO3, AllAgainstFiniteDifferencesAndJets) { checkAllJacobians<SO3>("SO3", 31); }
TEST(LieJacobiansSE3, AllAgainstFiniteDifferencesAndJets) { checkAllJacobians<SE3>("SE3", 32); }

#ifdef LIEFLOW_HAVE_CERES
// Jet derivatives through exp and log at θ = 0 exactly are finite and exact:
// ∂exp(δ)/∂δ = I (through the matrix) and ∂log(exp(δ))/∂δ = I, with no NaN
// from √0 in any branch; also through Jr, Jr⁻¹ and SE(3)'s Q at 0.
template <template <typename> class GroupT>
void expectExactJetDerivativesAtZero() {
  using GJ = GroupT<Jet>;
  constexpr int n = GJ::DoF;
  using Tan = Eigen::Matrix<double, n, 1>;
  const auto delta = seed<n>(Tan::Zero());
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  const GJ E = GJ::exp(delta);
  const Eigen::MatrixXd d_exp = jetRightJacobianOfGroup(E);
  ASSERT_TRUE(d_exp.allFinite()) << d_exp;
  EXPECT_EQ(d_exp, I);
  const Eigen::MatrixXd d_log = jetJacobian(E.log(), n);
  ASSERT_TRUE(d_log.allFinite()) << d_log;
  EXPECT_EQ(d_log, I);
  // Derivatives of the Jacobian matrices themselves at 0: ∂Jr/∂δ_k = −½ ad(e_k),
  // ∂Jr⁻¹/∂δ_k = +½ ad(e_k) (first-order terms of their series).
  const auto Jr = GJ::Jr(delta), JrInv = GJ::JrInv(delta);
  for (int k = 0; k < n; ++k) {
    const Eigen::MatrixXd ad_k = GroupT<double>::ad(Tan::Unit(k));
    const Eigen::MatrixXd dJr = derivative(Jr, k), dJrInv = derivative(JrInv, k);
    ASSERT_TRUE(dJr.allFinite() && dJrInv.allFinite());
    EXPECT_LE((dJr + 0.5 * ad_k).norm(), 1e-16) << "k = " << k;
    EXPECT_LE((dJrInv - 0.5 * ad_k).norm(), 1e-16) << "k = " << k;
  }
}

TEST(LieJacobiansSO3, JetDerivativesExactAtZero) { expectExactJetDerivativesAtZero<SO3>(); }
TEST(LieJacobiansSE3, JetDerivativesExactAtZero) { expectExactJetDerivativesAtZero<SE3>(); }

// The closed-form Jacobian matrices Jr, Jl, Jr⁻¹, Jl⁻¹ (and for SE(3) the
// block Q inside them) have correct Jet derivatives w.r.t. their argument in
// every branch, in particular across the series/closed-form switches: each
// ∂J/∂w_k from Jets agrees with central differences of J (relative 1e-7).
template <template <typename> class GroupT>
void checkJacobianMatrixDerivatives(const std::string& group) {
  using G = GroupT<double>;
  using GJ = GroupT<Jet>;
  constexpr int n = G::DoF;
  using Tan = Eigen::Matrix<double, n, 1>;
  using Fn = Eigen::MatrixXd (*)(const Tan&);
  using FnJ = Eigen::Matrix<Jet, n, n> (*)(const Eigen::Matrix<Jet, n, 1>&);
  struct Entry {
    const char* name;
    Fn f;
    FnJ fJ;
  };
  const Entry entries[] = {
      {"Jr", [](const Tan& w) -> Eigen::MatrixXd { return G::Jr(w); }, &GJ::Jr},
      {"Jl", [](const Tan& w) -> Eigen::MatrixXd { return G::Jl(w); }, &GJ::Jl},
      {"JrInv", [](const Tan& w) -> Eigen::MatrixXd { return G::JrInv(w); }, &GJ::JrInv},
      {"JlInv", [](const Tan& w) -> Eigen::MatrixXd { return G::JlInv(w); }, &GJ::JlInv},
  };
  std::vector<AngleBand> bands = standardBands();
  for (const auto& b : thresholdBands()) bands.push_back(b);
  Rng rng(41);
  for (const Entry& e : entries) {
    MaxTracker worst;
    for (const AngleBand& band : bands) {
      for (int s = 0; s < (band.theta == 0.0 ? 1 : 50); ++s) {
        const Tan w = sampleTangent<G>(band, rng);
        const auto J = e.fJ(seed<n>(w));
        Eigen::MatrixXd jet(n * n, n), fd(n * n, n);
        for (int k = 0; k < n; ++k) {
          const Eigen::MatrixXd dk = derivative(J, k);
          jet.col(k) = Eigen::Map<const Eigen::VectorXd>(dk.data(), n * n);
          const double h = 1e-6;
          const Eigen::MatrixXd diff = (e.f(w + h * Tan::Unit(k)) - e.f(w - h * Tan::Unit(k))) / (2 * h);
          fd.col(k) = Eigen::Map<const Eigen::VectorXd>(diff.data(), n * n);
        }
        std::ostringstream at;
        at << band.name << ", w = [" << w.transpose() << "]";
        worst.update(jet.allFinite() ? relativeError(jet, fd) : NAN, at.str());
      }
    }
    std::cout << "[ measured ] " << group << " d" << e.name << "/dw, Jet vs FD, worst relative "
              << worst.value << " at " << worst.where << std::endl;
    EXPECT_LE(worst.value, kTolerance) << group << " d" << e.name << "/dw at " << worst.where;
  }
}

TEST(LieJacobiansSO3, JacobianMatricesHaveCorrectJetDerivatives) {
  checkJacobianMatrixDerivatives<SO3>("SO3");
}
TEST(LieJacobiansSE3, JacobianMatricesHaveCorrectJetDerivatives) {
  checkJacobianMatrixDerivatives<SE3>("SE3");
}
#endif  // LIEFLOW_HAVE_CERES

}  // namespace
}  // namespace test
}  // namespace lieflow

