/// Three-stage Radau IIA (integrators/radau_iia.hpp): its coefficients and
/// stability function against the textbook properties, order 5 measured on a
/// damped oscillator (closed form) and on a free rigid body on SO(3) (the
/// exact flow by elliptic functions), a stiff dashpot damped out in one step
/// with its linear invariant kept, and a Newton iteration that cannot
/// converge reported as such.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <array>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dynamics/rigid_body/exact_free_body.hpp"
#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "integrators/lu_substitution.hpp"
#include "integrators/radau_iia.hpp"
#include "integrators/vector_state.hpp"
#include "tests/order_slope.hpp"

namespace lieflow {
namespace {

using testing_support::logLogSlope;

/// R(z) = 1 + z bᵀ(I − zA)⁻¹ 1, b the last row of A.
std::complex<double> stabilityFunction(const RadauIIACoefficients& k, std::complex<double> z) {
  const Eigen::Matrix3cd M = Eigen::Matrix3cd::Identity() - z * k.A.cast<std::complex<double>>();
  const Eigen::Vector3cd x = M.partialPivLu().solve(Eigen::Vector3cd::Ones());
  return 1.0 + z * (k.A.row(2).cast<std::complex<double>>() * x)(0);
}

TEST(RadauIIA, CoefficientsAreTheTextbookOnes) {
  const RadauIIACoefficients& k = RadauIIACoefficients::get();
  // Row sums are the nodes; the weights b are the last row (stiffly accurate).
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(k.A.row(i).sum(), k.c[static_cast<std::size_t>(i)], 1e-15);
  // The simplifying conditions B(5): Σ b_i c_i^(q−1) = 1/q, q = 1..5.
  for (int q = 1; q <= 5; ++q) {
    double s = 0.0;
    for (int i = 0; i < 3; ++i) s += k.A(2, i) * std::pow(k.c[static_cast<std::size_t>(i)], q - 1);
    EXPECT_NEAR(s, 1.0 / q, 1e-15) << "q = " << q;
  }
  // C(3): Σ_j a_ij c_j^(q−1) = c_i^q / q.
  for (int i = 0; i < 3; ++i)
    for (int q = 1; q <= 3; ++q) {
      double s = 0.0;
      for (int j = 0; j < 3; ++j) s += k.A(i, j) * std::pow(k.c[static_cast<std::size_t>(j)], q - 1);
      EXPECT_NEAR(s, std::pow(k.c[static_cast<std::size_t>(i)], q) / q, 1e-15);
    }
  // The transformation: T⁻¹ A⁻¹ T = [[γ, 0, 0], [0, α, −β], [0, β, α]].
  Eigen::Matrix3d L;
  L << k.gamma, 0, 0, 0, k.alpha, -k.beta, 0, k.beta, k.alpha;
  EXPECT_LT((k.T_inv * k.A.inverse() * k.T - L).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(k.beta, 0.0);
}

TEST(RadauIIA, StabilityFunctionIsAnOrderFiveLStableApproximationOfExp) {
  const RadauIIACoefficients& k = RadauIIACoefficients::get();
  // Error constant of the (2, 3) Padé approximant: R(z) − eᶻ = O(z⁶).
  const double e1 = std::abs(stabilityFunction(k, -0.1) - std::exp(-0.1));
  const double e2 = std::abs(stabilityFunction(k, -0.05) - std::exp(-0.05));
  std::printf("Radau IIA: |R(z) - exp(z)| %.3e at z = -0.1, %.3e at -0.05 (ratio 2^%.3f)\n", e1, e2,
              std::log2(e1 / e2));
  EXPECT_NEAR(std::log2(e1 / e2), 6.0, 0.1);
  // L-stable: |R| ≤ 1 on the imaginary axis and R(z) → 0 as z → −∞ (as 1/z).
  for (double y : {0.1, 1.0, 10.0, 1e3, 1e6}) EXPECT_LE(std::abs(stabilityFunction(k, {0.0, y})), 1.0 + 1e-14);
  EXPECT_LT(std::abs(stabilityFunction(k, -1e6)), 1e-5);
  EXPECT_LT(std::abs(stabilityFunction(k, -1e8)), 1e-7);
}

/// x'' + 2ζω x' + ω² x = 0 from (1, 0): the closed form.
double dampedOscillator(double t, double zeta, double omega) {
  const double wd = omega * std::sqrt(1.0 - zeta * zeta);
  return std::exp(-zeta * omega * t) * (std::cos(wd * t) + zeta * omega / wd * std::sin(wd * t));
}

TEST(RadauIIA, FifthOrderOnADampedOscillator) {
  using System = LinearSecondOrderSystem<double, 1>;
  const double zeta = 0.1, omega = 2.0, T = 4.0;
  const System sys(System::Matrix::Identity(), System::Matrix::Constant(2.0 * zeta * omega),
                   System::Matrix::Constant(omega * omega));
  RadauOptions o;
  o.tolerance = 1e-15;
  std::vector<double> hs, es;
  for (double h : {0.2, 0.1, 0.05, 0.025}) {
    const RadauIIAStepper<VectorState<double, 1>> stepper(o);
    VectorState<double, 1> y;
    y.x[0] = 1.0;
    const long n = std::lround(T / h);
    for (long i = 0; i < n; ++i) {
      StepReport report;
      y = stepper.step(sys, static_cast<double>(i) * h, y, h, &report);
      ASSERT_TRUE(report.converged) << report.failure;
    }
    hs.push_back(h);
    es.push_back(std::abs(y.x[0] - dampedOscillator(T, zeta, omega)));
  }
  const double slope = logLogSlope(hs, es);
  std::printf("Radau IIA, damped oscillator: errors %.3e .. %.3e, slope %.3f\n", es.front(), es.back(), slope);
  EXPECT_NEAR(slope, 5.0, 0.25);
}

TEST(RadauIIA, FifthOrderOnAFreeRigidBody) {
  RigidBodyParameters<double> p;
  p.inertia = Eigen::Vector3d(2.0, 3.0, 4.5).asDiagonal();
  const RotorSystem<double> sys(p);
  RotorState<double> y0;
  y0.R = SO3d::exp(Eigen::Vector3d(0.3, -0.2, 0.5));
  y0.omega = Eigen::Vector3d(1.2, -0.7, 0.9);
  const double T = 5.0;
  const ExactFreeRigidBody exact(p.inertia, y0.R.quaternion(), y0.omega);
  Eigen::Quaterniond q_exact;
  Eigen::Vector3d w_exact;
  exact.evaluate(T, &q_exact, &w_exact);
  RadauOptions o;
  o.tolerance = 1e-15;
  std::vector<double> hs, er, ew;
  for (double h : {0.1, 0.05, 0.025, 0.0125}) {
    const RadauIIAStepper<RotorState<double>> stepper(o);
    RotorState<double> y = y0;
    const long n = std::lround(T / h);
    for (long i = 0; i < n; ++i) y = stepper.step(sys, static_cast<double>(i) * h, y, h);
    hs.push_back(h);
    er.push_back((SO3d(q_exact).inverse() * y.R).log().norm());
    ew.push_back((y.omega - w_exact).norm());
  }
  const double sr = logLogSlope(hs, er), sw = logLogSlope(hs, ew);
  std::printf("Radau IIA, free rigid body: rotation errors %.3e .. %.3e slope %.3f; omega %.3e .. %.3e slope %.3f\n",
              er.front(), er.back(), sr, ew.front(), ew.back(), sw);
  EXPECT_NEAR(sr, 5.0, 0.3);
  EXPECT_NEAR(sw, 5.0, 0.3);
}

TEST(RadauIIA, StiffDashpotIsDampedInOneStepKeepingItsInvariant) {
  // x'' = −λ x': the rate decays as e^(−λt) and λx + x' is invariant (any
  // Runge–Kutta method keeps a linear invariant). hλ = 1e5.
  using System = LinearSecondOrderSystem<double, 1>;
  const double lambda = 1e6, h = 0.1;
  const System sys(System::Matrix::Identity(), System::Matrix::Constant(lambda), System::Matrix::Zero());
  const RadauIIAStepper<VectorState<double, 1>> stepper;
  VectorState<double, 1> y;
  y.v[0] = 3.0;
  const double invariant = lambda * y.x[0] + y.v[0];
  StepReport report;
  const VectorState<double, 1> y1 = stepper.step(sys, 0.0, y, h, &report);
  ASSERT_TRUE(report.converged) << report.failure;
  std::printf("Radau IIA, h lambda = 1e5: rate 3 -> %.3e, invariant change %.3e, %d Newton iterations\n",
              y1.v[0], lambda * y1.x[0] + y1.v[0] - invariant, report.newton_iterations);
  EXPECT_LT(std::abs(y1.v[0]), 3.0 * 1e-4);  // |R(−1e5)| ~ 1/(hλ)
  EXPECT_NEAR(lambda * y1.x[0] + y1.v[0], invariant, 1e-9 * lambda * std::abs(y1.x[0]));
  EXPECT_NEAR(y1.x[0], 3.0 / lambda, 1e-4 * 3.0 / lambda);  // near the rest position x₀ + v₀/λ
}

TEST(RadauIIA, ANewtonIterationThatCannotConvergeIsReported) {
  using System = LinearSecondOrderSystem<double, 1>;
  const System sys = System::oscillator(3.0);
  RadauOptions o;
  o.max_iterations = 1;
  o.tolerance = 1e-16;
  const RadauIIAStepper<VectorState<double, 1>> stepper(o);
  VectorState<double, 1> y;
  y.x[0] = 1.0;
  StepReport report;
  (void)stepper.step(sys, 0.0, y, 0.5, &report);
  EXPECT_FALSE(report.converged);
  EXPECT_NE(std::string(report.failure).find("Radau IIA"), std::string::npos);
  EXPECT_GT(report.newton_iterations, 0);
}

TEST(RadauIIA, TheJacobianIsKeptWhileNewtonContracts) {
  // A linear system: the first Jacobian is exact, Newton converges in one
  // iteration from any start, and no second Jacobian is needed.
  using System = LinearSecondOrderSystem<double, 1>;
  const System sys(System::Matrix::Identity(), System::Matrix::Constant(0.5), System::Matrix::Constant(4.0));
  const RadauIIAStepper<VectorState<double, 1>> stepper;
  VectorState<double, 1> y;
  y.x[0] = 1.0;
  for (int i = 0; i < 50; ++i) y = stepper.step(sys, 0.01 * i, y, 0.01);
  EXPECT_EQ(stepper.jacobianCount(), 1);
}

template <typename Scalar>
void expectSolvesAsEigensLu(int n) {
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  std::srand(3);
  const Matrix A = Matrix::Random(n, n) + Matrix::Identity(n, n);
  const Vector b = Vector::Random(n);
  LuSubstitution<Scalar> lu;
  lu.compute(A);
  Vector x(n);
  lu.solve(b, &x);
  const Vector reference = A.partialPivLu().solve(b);
  EXPECT_LT((x - reference).norm(), 1e-12 * reference.norm()) << "n = " << n;
  EXPECT_LT((A * x - b).norm(), 1e-12 * b.norm()) << "n = " << n;
}

TEST(LuSubstitution, SolvesAsEigensLu) {
  // Radau IIA's real and complex Newton systems, small and larger.
  for (int n : {1, 6, 40}) {
    expectSolvesAsEigensLu<double>(n);
    expectSolvesAsEigensLu<std::complex<double>>(n);
  }
}

/// A body on a strong, partly quadratic dashpot, x'' = −λ x' − μ x'|x'|,
/// counting its evaluations of f and saying, or not, that f does not depend
/// on t.
struct QuadraticDashpot {
  using State = VectorState<double, 1>;
  using Tangent = State::Tangent;
  double lambda = 240.0, mu = 10.0;
  bool says_autonomous = true;
  mutable int evaluations = 0;
  bool autonomous() const { return says_autonomous; }
  void velocity(double /*t*/, const State& y, Tangent* F) const {
    ++evaluations;
    (*F)[0] = y.v[0];
    (*F)[1] = -lambda * y.v[0] - mu * y.v[0] * std::abs(y.v[0]);
  }
};

TEST(RadauIIA, AStiffTransientStartsFromRestAndEvaluatesItOnce) {
  // hλ = 15: the motion dies within a few steps. The last step's polynomial
  // extrapolates that decay far beyond the step, so after the first steps
  // the stepper starts Newton from Z = 0, whose three stages are the one
  // point y: a system that says f does not depend on t is evaluated there
  // once, or not at all when a new Jacobian has just evaluated f(t, y) (k
  // iterations cost 1 + 3(k − 1) evaluations, or 3(k − 1) beside the
  // Jacobian's n + 1 = 3), with the same iterates (the same numbers) as one
  // that does not say so (3k).
  const double h = 0.0625;
  const int steps = 12, late = 4;
  std::array<QuadraticDashpot, 2> systems;
  systems[1].says_autonomous = false;
  std::array<VectorState<double, 1>, 2> ends;
  std::array<std::vector<int>, 2> iterations, evaluations, jacobians;
  for (std::size_t s = 0; s < 2; ++s) {
    const RadauIIAStepper<VectorState<double, 1>> stepper;
    VectorState<double, 1> y;
    y.x[0] = 1.0;
    y.v[0] = 3.0;
    for (int i = 0; i < steps; ++i) {
      StepReport report;
      const int before = systems[s].evaluations, jacobians_before = stepper.jacobianCount();
      y = stepper.step(systems[s], i * h, y, h, &report);
      ASSERT_TRUE(report.converged) << report.failure;
      iterations[s].push_back(report.newton_iterations);
      jacobians[s].push_back(stepper.jacobianCount() - jacobians_before);
      evaluations[s].push_back(systems[s].evaluations - before - 3 * jacobians[s].back());
    }
    ends[s] = y;
  }
  std::printf("Radau IIA, quadratic dashpot, h lambda = 15: %d evaluations (autonomous) against %d\n",
              systems[0].evaluations, systems[1].evaluations);
  EXPECT_EQ(ends[0].x[0], ends[1].x[0]);
  EXPECT_EQ(ends[0].v[0], ends[1].v[0]);
  EXPECT_EQ(iterations[0], iterations[1]);
  EXPECT_EQ(jacobians[0], jacobians[1]);
  for (int i = late; i < steps; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    EXPECT_EQ(evaluations[0][k], (jacobians[0][k] > 0 ? 0 : 1) + 3 * (iterations[0][k] - 1)) << "step " << i;
    EXPECT_EQ(evaluations[1][k], 3 * iterations[1][k]) << "step " << i;
  }
  EXPECT_LT(std::abs(ends[0].v[0]), 1e-12);
}

}  // namespace
}  // namespace lieflow
