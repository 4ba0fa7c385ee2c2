/// \file
/// Generic property tests of SO3<T> and SE3<T> (the manif pattern: one typed
/// suite over a list of groups), for T = double, float and, with Ceres,
/// ceres::Jet<double, 6> (values only here; derivatives in jacobians_test.cpp).
///
/// Every property is checked at the identity, near it (θ = 1e-9, 1e-5), at
/// random points (θ uniform in (0, π)) and near π (π − 1e-5, π − 1e-9). The
/// tolerances come from ScalarTraits<T> (float looser). References are the
/// group axioms and identities of Sola, Deray, Atchuthan 2018 ("A micro Lie
/// theory", §III–IV and App. B–D) and, for exp, an independent long double
/// matrix exponential of hat(ξ).
#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "test_helpers.hpp"

namespace lieflow {
namespace test {
namespace {

/// Random samples per band (the identity band has one sample: ξ = 0).
constexpr int kPerBand = 32;

template <typename G>
class LieGroupProperties : public ::testing::Test {
 public:
  using T = typename G::Scalar;
  using Traits = ScalarTraits<T>;
  using Tangent = typename G::Tangent;
  using TangentD = Eigen::Matrix<double, G::DoF, 1>;
  using Gd = typename Rebind<G>::template As<double>;

  static constexpr double tol = Traits::tol;

  /// Calls f(band, rng) once at the identity and kPerBand times in every other
  /// band, with a deterministic generator.
  template <typename F>
  static void forEachSample(std::uint64_t seed, F f) {
    Rng rng(seed);
    for (const AngleBand& band : standardBands()) {
      SCOPED_TRACE("band " + band.name);
      const int n = band.theta == 0.0 ? 1 : kPerBand;
      for (int i = 0; i < n; ++i) f(band, rng);
    }
  }

  static TangentD draw(const AngleBand& band, Rng& rng) { return sampleTangent<G>(band, rng); }
  static Tangent toT(const TangentD& xi) { return xi.template cast<T>(); }
  static G expT(const TangentD& xi) { return G::exp(toT(xi)); }

  /// Frobenius distance of the matrices, relative to max(1, ‖ref‖_F).
  static double dist(const G& a, const G& ref) {
    const auto m_ref = values(ref.matrix());
    return (values(a.matrix()) - m_ref).norm() / std::max(1.0, m_ref.norm());
  }

  /// ‖a − ref‖ / ‖ref‖ for tangents (‖a‖ when ref = 0): relative, so that the
  /// near-identity bands are checked to their own scale. For log(exp(ξ)),
  /// where nothing else rounds.
  template <typename V>
  static double tangentError(const V& a, const TangentD& ref) {
    const double d = (values(a) - ref).norm();
    return ref.norm() > 0.0 ? d / ref.norm() : d;
  }

  /// ‖a − ref‖ / max(1, ‖ref‖): for tangents recovered from products with
  /// unit-scale elements, whose rounding (ε‖X‖) is absolute, not relative to
  /// a small ref (Y ⊖ X of two nearby generic X, Y is only known to ~ε).
  template <typename V>
  static double tangentErrorAbs(const V& a, const TangentD& ref) {
    return (values(a) - ref).norm() / std::max(1.0, ref.norm());
  }

  /// log is single-valued below π: a rotation angle within a few rounding
  /// errors of π in the scalar's precision (float at π − 1e-9) may come back
  /// as the other representative ω − 2π ω/‖ω‖, so tangent round trips are
  /// only required below that.
  static bool logIsUnambiguous(const TangentD& xi) {
    return rotationPart(xi).norm() < kPi * (1.0 - 16.0 * Traits::eps);
  }
};

struct GroupName {
  template <typename G>
  static std::string GetName(int) {
    return std::string(Rebind<G>::name()) + "_" + ScalarTraits<typename G::Scalar>::name();
  }
};

using Groups = ::testing::Types<SO3d, SO3f, SE3d, SE3f
#ifdef LIEFLOW_HAVE_CERES
                                ,
                                SO3<Jet>, SE3<Jet>
#endif
                                >;
TYPED_TEST_SUITE(LieGroupProperties, Groups, GroupName);

// (XY)Z = X(YZ); XI = IX = X; XX⁻¹ = X⁻¹X = I; (XY)⁻¹ = Y⁻¹X⁻¹.
TYPED_TEST(LieGroupProperties, GroupAxioms) {
  using Fx = TestFixture;
  using G = TypeParam;
  const G I = G::identity();
  Fx::forEachSample(11, [&](const AngleBand& band, Rng& rng) {
    const G X = Fx::expT(Fx::draw(band, rng)), Y = Fx::expT(Fx::draw(band, rng)),
            Z = Fx::expT(Fx::draw(band, rng));
    EXPECT_LE(Fx::dist((X * Y) * Z, X * (Y * Z)), Fx::tol);
    EXPECT_LE(Fx::dist(X * I, X), Fx::tol);
    EXPECT_LE(Fx::dist(I * X, X), Fx::tol);
    EXPECT_LE(Fx::dist(X * X.inverse(), I), Fx::tol);
    EXPECT_LE(Fx::dist(X.inverse() * X, I), Fx::tol);
    EXPECT_LE(Fx::dist((X * Y).inverse(), Y.inverse() * X.inverse()), Fx::tol);
    G XY = X;
    XY *= Y;
    EXPECT_LE(Fx::dist(XY, X * Y), Fx::tol);
  });
}

// exp(log X) = X at every point; log(exp ξ) = ξ (relative) where log is
// single-valued; exp(0) = I and log(I) = 0 exactly; exp(ξ) is a unit quaternion.
TYPED_TEST(LieGroupProperties, ExpLogInverse) {
  using Fx = TestFixture;
  using G = TypeParam;
  using Tangent = typename G::Tangent;
  EXPECT_EQ(values(G::exp(Tangent::Zero()).matrix()), values(G::identity().matrix()));
  EXPECT_EQ(values(G::identity().log()).norm(), 0.0);
  Fx::forEachSample(12, [&](const AngleBand& band, Rng& rng) {
    const auto xi = Fx::draw(band, rng);
    const G X = Fx::expT(xi);
    EXPECT_LE(Fx::dist(G::exp(X.log()), X), Fx::tol) << "xi = " << xi.transpose();
    if (Fx::logIsUnambiguous(xi)) {
      EXPECT_LE(Fx::tangentError(X.log(), xi), Fx::tol) << "xi = " << xi.transpose();
    }
    EXPECT_LE(std::abs(values(X.quaternion().coeffs()).squaredNorm() - 1.0), 4 * Fx::Traits::eps);
  });
}

/// e^A by scaling and squaring of the Taylor series, in long double.
template <int N>
Eigen::Matrix<long double, N, N> expmLongDouble(const Eigen::Matrix<long double, N, N>& A) {
  int squarings = 0;
  long double norm = A.cwiseAbs().rowwise().sum().maxCoeff();
  while (norm > 0.25L) {
    norm *= 0.5L;
    ++squarings;
  }
  const Eigen::Matrix<long double, N, N> B = A / std::ldexp(1.0L, squarings);
  Eigen::Matrix<long double, N, N> E = Eigen::Matrix<long double, N, N>::Identity(),
                                   term = Eigen::Matrix<long double, N, N>::Identity();
  for (int k = 1; k <= 25; ++k) {
    term = term * B / static_cast<long double>(k);
    E += term;
  }
  for (int i = 0; i < squarings; ++i) E = E * E;
  return E;
}

// Independent reference for exp: exp(ξ).matrix() = e^{hat(ξ)} (the matrix
// exponential of the algebra element, long double scaling and squaring).
TYPED_TEST(LieGroupProperties, ExpIsTheMatrixExponentialOfHat) {
  using Fx = TestFixture;
  Fx::forEachSample(13, [&](const AngleBand& band, Rng& rng) {
    const auto xi = Fx::draw(band, rng);
    const auto A = Fx::Gd::hat(xi).template cast<long double>().eval();
    const auto E = expmLongDouble(A).template cast<double>().eval();
    const auto M = values(Fx::expT(xi).matrix());
    EXPECT_LE((M - E).norm() / E.norm(), Fx::tol) << "xi = " << xi.transpose();
  });
}

// exp(Adj(X) ξ) = X exp(ξ) X⁻¹, Adj(XY) = Adj(X) Adj(Y), Adj(X⁻¹) = Adj(X)⁻¹.
TYPED_TEST(LieGroupProperties, Adjoint) {
  using Fx = TestFixture;
  using G = TypeParam;
  Fx::forEachSample(14, [&](const AngleBand& band, Rng& rng) {
    const auto xi = Fx::draw(band, rng);
    const G X = Fx::expT(Fx::draw(band, rng)), Y = Fx::expT(Fx::draw(band, rng));
    const typename G::Tangent adj_xi = X.Adj() * Fx::toT(xi);
    const G conj = X * G::exp(Fx::toT(xi)) * X.inverse();
    EXPECT_LE(Fx::dist(G::exp(adj_xi), conj), Fx::tol) << "xi = " << xi.transpose();
    // Relative to ξ as a tangent, where the log of the conjugate is single-valued.
    if (Fx::logIsUnambiguous(xi)) {
      EXPECT_LE(Fx::tangentErrorAbs(conj.log(), values(adj_xi)), Fx::tol);
    }
    const auto A_XY = values((X * Y).Adj());
    EXPECT_LE((A_XY - values(X.Adj()) * values(Y.Adj())).norm() / A_XY.norm(), Fx::tol);
    const auto A_Xinv = values(X.inverse().Adj());
    EXPECT_LE((A_Xinv * values(X.Adj()) - Eigen::Matrix<double, G::DoF, G::DoF>::Identity()).norm(), Fx::tol);
  });
}

// vee(hat ξ) = ξ; hat is linear and skew on the rotation block; the bracket
// of the algebra is ad: vee([hat a, hat b]) = ad_a b; ad_a a = 0.
TYPED_TEST(LieGroupProperties, HatVeeAndAd) {
  using Fx = TestFixture;
  using G = TypeParam;
  Fx::forEachSample(15, [&](const AngleBand& band, Rng& rng) {
    const typename G::Tangent aT = Fx::toT(Fx::draw(band, rng)), bT = Fx::toT(Fx::draw(band, rng));
    const typename Fx::TangentD a = values(aT), b = values(bT);
    const auto A = G::hat(aT), B = G::hat(bT);
    // Exact, compared in T (GCC 12 -O2 may fold a double→float→double round
    // trip of Eigen 3-vectors away, so a need not be exactly aT's value).
    EXPECT_TRUE((G::vee(A).array() == aT.array()).all()) << a.transpose();
    const auto R = A.template topLeftCorner<3, 3>();
    EXPECT_EQ(values(R + R.transpose()).norm(), 0.0);
    const typename G::Tangent bracket = G::vee((A * B - B * A).eval());
    const typename G::Tangent ad_ab = G::ad(aT) * bT;
    const double scale = std::max(a.norm() * b.norm(), 1e-300);
    EXPECT_LE((values(bracket) - values(ad_ab)).norm(), Fx::tol * scale);
    EXPECT_LE(values(G::ad(aT) * aT).norm(), Fx::tol * std::max(a.squaredNorm(), 1e-300));
    if constexpr (G::DoF == 3) {  // hat(w) v = w × v
      EXPECT_LE((values(A * bT) - a.cross(b)).norm(), Fx::tol * scale);
    } else {  // last row of an se(3) element is zero
      EXPECT_EQ(values(A.row(3)).norm(), 0.0);
    }
  });
}

// Jl(ξ) = Jr(−ξ); Jl(ξ) = Adj(exp ξ) Jr(ξ); Jr⁻¹ Jr = Jr Jr⁻¹ = I; Jl⁻¹ Jl = I.
TYPED_TEST(LieGroupProperties, JacobianIdentities) {
  using Fx = TestFixture;
  using G = TypeParam;
  Fx::forEachSample(16, [&](const AngleBand& band, Rng& rng) {
    const auto xi = Fx::draw(band, rng);
    const typename G::Tangent x = Fx::toT(xi);
    const auto Jr = values(G::Jr(x)), Jl = values(G::Jl(x));
    const Eigen::Matrix<double, G::DoF, G::DoF> I = Eigen::Matrix<double, G::DoF, G::DoF>::Identity();
    EXPECT_LE((Jl - values(G::Jr((-x).eval()))).norm(), Fx::tol) << "xi = " << xi.transpose();
    EXPECT_LE((Jl - values(G::exp(x).Adj()) * Jr).norm(), Fx::tol) << "xi = " << xi.transpose();
    EXPECT_LE((values(G::JrInv(x)) * Jr - I).norm(), Fx::tol) << "xi = " << xi.transpose();
    EXPECT_LE((Jr * values(G::JrInv(x)) - I).norm(), Fx::tol) << "xi = " << xi.transpose();
    EXPECT_LE((values(G::JlInv(x)) * Jl - I).norm(), Fx::tol) << "xi = " << xi.transpose();
    EXPECT_LE((values(G::JlInv(x)) - values(G::JrInv((-x).eval()))).norm(), Fx::tol);
  });
}

// matrix() is a homomorphism: (XY).matrix() = X.matrix() Y.matrix(),
// X⁻¹.matrix() = X.matrix()⁻¹; the action is the matrix acting on the point
// (homogeneous for SE(3)); the rotation block is orthonormal with det +1.
TYPED_TEST(LieGroupProperties, MatrixConsistency) {
  using Fx = TestFixture;
  using G = TypeParam;
  using T = typename G::Scalar;
  Fx::forEachSample(17, [&](const AngleBand& band, Rng& rng) {
    const G X = Fx::expT(Fx::draw(band, rng)), Y = Fx::expT(Fx::draw(band, rng));
    const auto MX = values(X.matrix()), MY = values(Y.matrix());
    EXPECT_LE((values((X * Y).matrix()) - MX * MY).norm(), Fx::tol * (1 + MX.norm() * MY.norm()));
    EXPECT_LE((values(X.inverse().matrix()) * MX - std::decay_t<decltype(MX)>::Identity()).norm(),
              Fx::tol * (1 + MX.norm()));
    const Eigen::Vector3d p = 2.0 * randomInBall(rng);
    const Vector3<T> Xp = X * p.cast<T>().eval();
    Eigen::Vector3d expected;
    if constexpr (G::DoF == 3) {
      expected = MX * p;
    } else {
      expected = (MX * p.homogeneous()).template head<3>();
    }
    EXPECT_LE((values(Xp) - expected).norm(), Fx::tol * (1 + MX.norm() * p.norm()));
    const Eigen::Matrix3d R = MX.template topLeftCorner<3, 3>();
    EXPECT_LE((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), Fx::tol);
    EXPECT_NEAR(R.determinant(), 1.0, Fx::tol);
  });
}

// X.interpolate(Y, 0) = X, X.interpolate(Y, 1) = Y, and the midpoint M splits
// the geodesic evenly: M ⊖ X = Y ⊖ M = (Y ⊖ X)/2. Y = X ⊕ τ with τ in the band
// and X random, so tangents are compared to the absolute rounding of X.
TYPED_TEST(LieGroupProperties, InterpolateEndpointsAndMidpoint) {
  using Fx = TestFixture;
  using G = TypeParam;
  using T = typename G::Scalar;
  Fx::forEachSample(18, [&](const AngleBand& band, Rng& rng) {
    const G X = Fx::expT(Fx::draw(AngleBand{"random", -1.0}, rng));
    const auto tau = Fx::draw(band, rng);
    const G Y = X.rplus(Fx::toT(tau));
    EXPECT_LE(Fx::dist(X.interpolate(Y, T(0)), X), Fx::tol);
    EXPECT_LE(Fx::dist(X.interpolate(Y, T(1)), Y), Fx::tol);
    const G M = X.interpolate(Y, T(0.5));
    // Whichever representative Y ⊖ X returned (both are geodesics at π).
    const Eigen::Matrix<double, G::DoF, 1> half = 0.5 * values(Y.rminus(X));
    EXPECT_LE(Fx::tangentErrorAbs(M.rminus(X), half), Fx::tol) << "tau = " << tau.transpose();
    EXPECT_LE(Fx::tangentErrorAbs(Y.rminus(M), half), Fx::tol) << "tau = " << tau.transpose();
    if (Fx::logIsUnambiguous(tau)) {
      EXPECT_LE(Fx::tangentErrorAbs(M.rminus(X), 0.5 * tau), Fx::tol);
    }
  });
}

// (X ⊕ τ) ⊖ X = τ (where log is single-valued; X random, so to absolute
// rounding) and X ⊕ (Y ⊖ X) = Y.
TYPED_TEST(LieGroupProperties, RplusRminusRoundTrip) {
  using Fx = TestFixture;
  using G = TypeParam;
  Fx::forEachSample(19, [&](const AngleBand& band, Rng& rng) {
    const G X = Fx::expT(Fx::draw(AngleBand{"random", -1.0}, rng));
    const auto tau = Fx::draw(band, rng);
    if (Fx::logIsUnambiguous(tau)) {
      EXPECT_LE(Fx::tangentErrorAbs(X.rplus(Fx::toT(tau)).rminus(X), tau), Fx::tol) << tau.transpose();
    }
    const G Y = Fx::expT(Fx::draw(band, rng)) * X;
    EXPECT_LE(Fx::dist(X.rplus(Y.rminus(X)), Y), Fx::tol);
  });
}

// normalize() re-projects a long unnormalized product onto the group: unit
// quaternion to a few ε, the same motion to the drift accumulated, and the
// in-place and copying forms agree. isApprox accepts X ≈ X and rejects a
// perturbation of 1e-3 at tolerance 1e-4.
TYPED_TEST(LieGroupProperties, NormalizeAndIsApprox) {
  using Fx = TestFixture;
  using G = TypeParam;
  Fx::forEachSample(20, [&](const AngleBand& band, Rng& rng) {
    G P = G::identity();
    for (int i = 0; i < 200; ++i) P = P * Fx::expT(Fx::draw(band, rng));
    const G N = P.normalized();
    EXPECT_LE(std::abs(values(N.quaternion().coeffs()).norm() - 1.0), 4 * Fx::Traits::eps);
    EXPECT_LE(Fx::dist(N, P), 200 * Fx::tol);
    G Q = P;
    Q.normalize();
    EXPECT_EQ(values(Q.matrix()), values(N.matrix()));
    EXPECT_TRUE(N.isApprox(N, Fx::tol));
    typename Fx::TangentD d = Fx::TangentD::Zero();
    d[0] = 1e-3;
    EXPECT_FALSE(N.isApprox(N.rplus(Fx::toT(d)), 1e-4));
  });
}

// cast: a double element cast to T equals the element computed in T (within
// T's tolerance); float/double cast back and forth; Jets get zero derivatives.
TYPED_TEST(LieGroupProperties, Cast) {
  using Fx = TestFixture;
  using G = TypeParam;
  using T = typename G::Scalar;
  Fx::forEachSample(21, [&](const AngleBand& band, Rng& rng) {
    const auto xi = Fx::draw(band, rng);
    const typename Fx::Gd Xd = Fx::Gd::exp(xi);
    const G X = Xd.template cast<T>();
    EXPECT_LE(Fx::dist(X, Fx::expT(xi)), Fx::tol);
    if constexpr (!Fx::Traits::is_jet) {
      EXPECT_LE((X.template cast<double>().matrix() - Xd.matrix()).norm(), Fx::tol);
      // float → double → float is exact.
      EXPECT_EQ(X.template cast<double>().template cast<T>().matrix(), X.matrix());
    } else {
#ifdef LIEFLOW_HAVE_CERES
      for (int k = 0; k < 6; ++k) EXPECT_EQ(derivative(X.matrix(), k).norm(), 0.0);
#endif
    }
  });
}

// ---- conventions (DESIGN.md "Conventions"), double only ---------------------------

// Hamilton quaternion (w, x, y, z), right-handed: exp(θ e_z) = (cos θ/2, 0, 0,
// sin θ/2) and maps e_x to (cos θ, sin θ, 0).
TEST(LieConventions, SO3ExpIsRightHandedHamilton) {
  const double theta = 0.7;
  const SO3d R = SO3d::exp(Eigen::Vector3d(0, 0, theta));
  EXPECT_NEAR(R.quaternion().w(), std::cos(theta / 2), 1e-16);
  EXPECT_NEAR(R.quaternion().z(), std::sin(theta / 2), 1e-16);
  EXPECT_LE((R * Eigen::Vector3d::UnitX() - Eigen::Vector3d(std::cos(theta), std::sin(theta), 0)).norm(),
            1e-15);
}

// SE(3) tangents are (ρ, ω): exp((ρ, 0)) is the pure translation ρ, and
// exp((0, ω)) the pure rotation; X p = R p + t.
TEST(LieConventions, SE3TangentIsTranslationThenRotation) {
  Eigen::Matrix<double, 6, 1> xi;
  xi << 1, 2, 3, 0, 0, 0;
  EXPECT_EQ(SE3d::exp(xi).translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(SE3d::exp(xi).rotation().matrix(), Eigen::Matrix3d::Identity());
  xi << 0, 0, 0, 0, 0, 0.5;
  EXPECT_EQ(SE3d::exp(xi).translation(), Eigen::Vector3d::Zero());
  EXPECT_LE((SE3d::exp(xi).rotation().matrix() - SO3d::exp(Eigen::Vector3d(0, 0, 0.5)).matrix()).norm(),
            1e-16);
  const SE3d X(SO3d::exp(Eigen::Vector3d(0.1, -0.2, 0.3)), Eigen::Vector3d(4, 5, 6));
  const Eigen::Vector3d p(1, -1, 2);
  EXPECT_LE((X * p - (X.rotation().matrix() * p + X.translation())).norm(), 1e-14);
}

}  // namespace
}  // namespace test
}  // namespace lieflow
