/// \file
/// Bad input to the checked factories of SO3 and SE3: each rejection throws
/// lieflow::InvalidInput whose message names the field passed in (and
/// field() returns it); near-unit input within the 1e-6 tolerance is accepted
/// and projected onto the group. Plus the debug-build assert of the unchecked
/// constructor (DEVELOPERS.md: bad input gets a clear error naming the field).
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_helpers.hpp"

namespace lieflow {
namespace test {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

/// Runs f, which must throw InvalidInput whose field() is `field` and whose
/// message contains `field` and every one of `words`.
template <typename F>
void expectInvalidInput(F f, const std::string& field, std::vector<std::string> words = {}) {
  try {
    f();
    ADD_FAILURE() << "no InvalidInput thrown (field " << field << ")";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.field(), field) << what;
    EXPECT_NE(what.find(field), std::string::npos) << what;
    for (const auto& w : words) EXPECT_NE(what.find(w), std::string::npos) << "'" << w << "' in: " << what;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

// ---- SO3::fromQuaternionChecked --------------------------------------------------

TEST(LieCheckedInputSO3, QuaternionRejectsNonFinite) {
  const std::string field = "bodies[2].orientation";
  for (int i = 0; i < 4; ++i)
    for (double bad : {kNaN, kInf, -kInf}) {
      Eigen::Vector4d c(0.5, 0.5, 0.5, 0.5);  // (w, x, y, z), unit
      c[i] = bad;
      expectInvalidInput([&] { SO3d::fromQuaternionChecked(Eigen::Quaterniond(c[0], c[1], c[2], c[3]), field); },
                         field, {"non-finite"});
    }
}

TEST(LieCheckedInputSO3, QuaternionRejectsWrongNorm) {
  const std::string field = "bodies[0].orientation";
  expectInvalidInput([&] { SO3d::fromQuaternionChecked(Eigen::Quaterniond(0, 0, 0, 0), field); }, field,
                     {"norm"});
  expectInvalidInput([&] { SO3d::fromQuaternionChecked(Eigen::Quaterniond(1.1, 0, 0, 0), field); }, field,
                     {"norm", "1.1"});
  // 0.1 · unit → norm 0.1; just beyond the 1e-6 tolerance on both sides.
  expectInvalidInput([&] { SO3d::fromQuaternionChecked(Eigen::Quaterniond(0.05, 0.05, 0.05, 0.05), field); },
                     field);
  expectInvalidInput([&] { SO3d::fromQuaternionChecked(Eigen::Quaterniond(1 + 2e-6, 0, 0, 0), field); },
                     field);
  expectInvalidInput([&] { SO3d::fromQuaternionChecked(Eigen::Quaterniond(1 - 2e-6, 0, 0, 0), field); },
                     field);
  // The default field name is used when none is given.
  expectInvalidInput([&] { SO3d::fromQuaternionChecked(Eigen::Quaterniond(2, 0, 0, 0)); }, "quaternion");
}

// Near-unit input (norm 1 ± 1e-8) is accepted and normalized; the rotation is
// that of the normalized input.
TEST(LieCheckedInputSO3, QuaternionAcceptsAndNormalizesNearUnit) {
  Rng rng(71);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Quaterniond unit = SO3d::random(rng).quaternion();
    for (double scale : {1 + 1e-8, 1 - 1e-8, 1 + 9e-7}) {
      const Eigen::Quaterniond q(scale * unit.coeffs());
      const SO3d R = SO3d::fromQuaternionChecked(q, "q");
      EXPECT_LE(std::abs(R.quaternion().norm() - 1.0), 4e-16);
      EXPECT_LE((R.matrix() - unit.toRotationMatrix()).norm(), 4e-15);
    }
  }
  const SO3f Rf = SO3f::fromQuaternionChecked(Eigen::Quaternionf(1.0f + 1e-7f, 0, 0, 0), "qf");
  EXPECT_LE(std::abs(Rf.quaternion().norm() - 1.0f), 2e-7f);
  expectInvalidInput([] { SO3f::fromQuaternionChecked(Eigen::Quaternionf(1.1f, 0, 0, 0), "qf"); }, "qf");
}

// ---- SO3::fromArrayChecked -----------------------------------------------------------

TEST(LieCheckedInputSO3, ArrayRejectsWrongSizeAndBadValues) {
  const std::string field = "initial.orientation";
  for (std::size_t n : {0u, 3u, 5u})
    expectInvalidInput([&] { SO3d::fromArrayChecked(std::vector<double>(n, 0.5), field); }, field,
                       {"4", std::to_string(n)});
  expectInvalidInput([&] { SO3d::fromArrayChecked(std::vector<double>{1, 0, kNaN, 0}, field); }, field);
  expectInvalidInput([&] { SO3d::fromArrayChecked(std::vector<double>{0, 0, 0, 0}, field); }, field);
  expectInvalidInput([&] { SO3d::fromArrayChecked(std::array<double, 4>{1.1, 0, 0, 0}, field); }, field);
  // (w, x, y, z) order: (cos π/4, 0, 0, sin π/4) is +90° about z.
  const double c = std::sqrt(0.5) * (1 + 1e-8);
  const SO3d R = SO3d::fromArrayChecked(std::vector<double>{c, 0, 0, c}, field);
  EXPECT_LE((R * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-15);
}

// ---- SO3::fromRotationMatrixChecked ---------------------------------------------------

TEST(LieCheckedInputSO3, RotationMatrixRejectsBadMatrices) {
  const std::string field = "joint.frame";
  const Eigen::Matrix3d R = SO3d::exp(Eigen::Vector3d(0.3, -0.2, 1.0)).matrix();
  for (double bad : {kNaN, kInf}) {
    Eigen::Matrix3d M = R;
    M(1, 2) = bad;
    expectInvalidInput([&] { SO3d::fromRotationMatrixChecked(M, field); }, field, {"non-finite"});
  }
  expectInvalidInput([&] { SO3d::fromRotationMatrixChecked(1.1 * R, field); }, field, {"orthonormal"});
  Eigen::Matrix3d shear = R;
  shear(0, 1) += 1e-3;
  expectInvalidInput([&] { SO3d::fromRotationMatrixChecked(shear, field); }, field, {"orthonormal"});
  expectInvalidInput([&] { SO3d::fromRotationMatrixChecked(Eigen::Matrix3d::Zero(), field); }, field);
  const Eigen::Matrix3d reflection = R * Eigen::Vector3d(1, 1, -1).asDiagonal();
  expectInvalidInput([&] { SO3d::fromRotationMatrixChecked(reflection, field); }, field, {"reflection"});
  expectInvalidInput([&] { SO3d::fromRotationMatrixChecked(-Eigen::Matrix3d::Identity(), field); }, field,
                     {"reflection"});
}

// A rotation perturbed by 1e-8 is accepted and projected onto SO(3).
TEST(LieCheckedInputSO3, RotationMatrixAcceptsAndProjectsNearRotation) {
  Rng rng(72);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Matrix3d R = SO3d::exp(std::uniform_real_distribution<double>(0, kPi)(rng) * randomUnit(rng)).matrix();
    Eigen::Matrix3d noise;
    for (int k = 0; k < 9; ++k) noise(k) = std::uniform_real_distribution<double>(-1, 1)(rng);
    const Eigen::Matrix3d M = R + 1e-8 * noise;
    const SO3d P = SO3d::fromRotationMatrixChecked(M, "frame");
    EXPECT_LE(std::abs(P.quaternion().norm() - 1.0), 4e-16);
    EXPECT_LE((P.matrix() - R).norm(), 1e-7);
  }
}

// ---- SE3 ------------------------------------------------------------------------------------

TEST(LieCheckedInputSE3, MatrixRejectsBadLastRowRotationAndTranslation) {
  const std::string field = "bodies[1].pose";
  Eigen::Matrix4d good = SE3d(SO3d::exp(Eigen::Vector3d(0.1, 0.2, 0.3)), Eigen::Vector3d(1, 2, 3)).matrix();
  for (const Eigen::Vector4d& row :
       {Eigen::Vector4d(0, 0, 0, 2), Eigen::Vector4d(0, 1, 0, 1), Eigen::Vector4d(0, 0, 0, 0),
        Eigen::Vector4d(kNaN, 0, 0, 1), Eigen::Vector4d(0, 0, 0, kInf)}) {
    Eigen::Matrix4d M = good;
    M.row(3) = row.transpose();
    expectInvalidInput([&] { SE3d::fromMatrixChecked(M, field); }, field, {"last row"});
  }
  Eigen::Matrix4d M = good;
  M.topLeftCorner<3, 3>() *= 1.1;
  expectInvalidInput([&] { SE3d::fromMatrixChecked(M, field); }, field + ".rotation", {"orthonormal"});
  M = good;
  M.topLeftCorner<3, 3>() = M.topLeftCorner<3, 3>() * Eigen::Vector3d(-1, 1, 1).asDiagonal();
  expectInvalidInput([&] { SE3d::fromMatrixChecked(M, field); }, field + ".rotation", {"reflection"});
  M = good;
  M(0, 0) = kNaN;
  expectInvalidInput([&] { SE3d::fromMatrixChecked(M, field); }, field + ".rotation");
  M = good;
  M(1, 3) = kNaN;
  expectInvalidInput([&] { SE3d::fromMatrixChecked(M, field); }, field + ".translation");
  // Accepted: a near-rigid matrix, projected; the translation kept.
  M = good;
  M.topLeftCorner<3, 3>() += 1e-8 * Eigen::Matrix3d::Ones();
  const SE3d X = SE3d::fromMatrixChecked(M, field);
  EXPECT_LE((X.matrix() - good).norm(), 1e-7);
  EXPECT_EQ(X.translation(), Eigen::Vector3d(1, 2, 3));
}

TEST(LieCheckedInputSE3, QuaternionTranslationRejectsBadParts) {
  const std::string field = "scene.bodies[3]";
  const Eigen::Quaterniond unit(1, 0, 0, 0);
  expectInvalidInput([&] { SE3d::fromQuaternionTranslationChecked(Eigen::Quaterniond(0, 0, 0, 0), Eigen::Vector3d::Zero(), field); },
                     field + ".orientation", {"norm"});
  expectInvalidInput([&] { SE3d::fromQuaternionTranslationChecked(Eigen::Quaterniond(1.1, 0, 0, 0), Eigen::Vector3d::Zero(), field); },
                     field + ".orientation");
  expectInvalidInput([&] { SE3d::fromQuaternionTranslationChecked(Eigen::Quaterniond(kNaN, 0, 0, 0), Eigen::Vector3d::Zero(), field); },
                     field + ".orientation", {"non-finite"});
  expectInvalidInput([&] { SE3d::fromQuaternionTranslationChecked(unit, Eigen::Vector3d(0, kInf, 0), field); },
                     field + ".position", {"non-finite"});
  expectInvalidInput([&] { SE3d::fromQuaternionTranslationChecked(unit, Eigen::Vector3d(kNaN, 0, 0), field); },
                     field + ".position");
  const SE3d X = SE3d::fromQuaternionTranslationChecked(Eigen::Quaterniond(1 + 1e-8, 0, 0, 0),
                                                        Eigen::Vector3d(4, 5, 6), field);
  EXPECT_EQ(X.quaternion().w(), 1.0);
  EXPECT_EQ(X.translation(), Eigen::Vector3d(4, 5, 6));
}

// ---- the unchecked fast path --------------------------------------------------------------

// In debug builds SO3(q) asserts that q has unit norm (its message says
// "unit"); release builds compile the check away (EXPECT_DEBUG_DEATH then
// just runs the statement).
TEST(LieCheckedInputDeathTest, UncheckedConstructorAssertsUnitNormInDebug) {
  EXPECT_DEBUG_DEATH(SO3d(Eigen::Quaterniond(2, 0, 0, 0)), "unit");
}

// The library's own float paths must satisfy that precondition: SO3f::random,
// SE3f::random, SO3d::cast<float>() and SO3f::cast<double>() build SO3
// through the asserting constructor, whose tolerance is 1e4 ε of the scalar's
// value type (ScalarValueTypeT: float for SO3f); cast to a more precise type
// re-projects onto the group. (A regression test: before that fix the float
// paths aborted in debug builds.)
void exerciseFloatPathsAndExit() {
  Rng rng(73);
  for (int i = 0; i < 100; ++i) {
    (void)SO3f::random(rng);
    (void)SE3f::random(rng);
    const SO3d R = SO3d::exp(randomUnit(rng));
    (void)R.cast<float>();
    (void)R.cast<float>().cast<double>();
  }
  std::exit(0);
}

TEST(LieCheckedInputDeathTest, FloatRandomAndCastKeepTheUnitNormPrecondition) {
  EXPECT_EXIT(exerciseFloatPathsAndExit(), ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace test
}  // namespace lieflow
