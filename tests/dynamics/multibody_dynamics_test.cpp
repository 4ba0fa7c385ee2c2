// Dynamics of constrained multibody systems (dynamics/maximal/multibody_system.hpp)
// stepped by the projected Lie-group steppers, against independent results.
#include <cmath>

#include <gtest/gtest.h>

#include "integrators/butcher_tableau.hpp"
#include "integrators/commutator_free.hpp"
#include "integrators/integrate.hpp"
#include "integrators/projected_stepper.hpp"
#include "integrators/rkmk.hpp"
#include "dynamics/maximal/multibody_system.hpp"
#include "tests/dynamics/pendulum_fixture.hpp"

namespace lieflow {
namespace multibody {
namespace {

using testing_support::Pendulum;

TEST(MultibodyDynamics, PendulumMatchesOneDimensionalReference) {
  const double theta0 = 1.2, T = 2.0;
  const Pendulum P(theta0);
  const double ref = P.reference(T);
  ProjectedStepper<RkmkStepper<MultibodyGroupState>> stepper{RkmkStepper<MultibodyGroupState>(ButcherTableau::rk4())};
  MultibodyGroupState y = P.y0;
  double max_err = 0.0;
  const RunSummary run = integrateFixedStep(stepper, P.system, y, 0.0, T, 1e-3,
                                            [&](long, double t, const MultibodyGroupState& s) {
                                              max_err = std::max(max_err, P.system.constraintError(t, s));
                                              y = s;
                                              return true;
                                            });
  ASSERT_FALSE(run.failed) << run.failure;
  // The joint angle is zero at assembly (t = 0): θ = θ₀ + φ_J.
  EXPECT_NEAR(theta0 + y.angles[0], ref, 1e-10);
  EXPECT_LE(max_err, 1e-12);
}

}  // namespace
}  // namespace multibody
}  // namespace lieflow
