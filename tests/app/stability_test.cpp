/// \file
/// The stability study against linear stability theory: on the stiff
/// torsional spring (small oscillation, ω_c = √(k/I_min) = 100 rad/s) the
/// largest bounded h·ω_c of an explicit method is the imaginary-axis limit of
/// its stability function: √3 for third-order RK (RKMK3, CG3), 2√2 for RK4
/// (RKMK4, CF4), 2 for the Störmer–Verlet-like splitting and LGVI.
#include <gtest/gtest.h>

#include <cmath>

#include "app/stability.hpp"

namespace lieflow {
namespace app {
namespace {

double limit(const std::string& integrator) {
  static const Simulation sim(loadScene("stiff-spring"));
  StabilityOptions o;
  o.integrators = {integrator};
  const std::vector<StabilityRow> rows = runStability(sim, o);
  EXPECT_EQ(rows.size(), 1u);
  return rows[0].h_omega_max;
}

TEST(StabilityStudy, ExplicitLimitsMatchLinearTheory) {
  EXPECT_NEAR(limit("rkmk3"), std::sqrt(3.0), 0.1);
  EXPECT_NEAR(limit("cg3"), std::sqrt(3.0), 0.1);
  EXPECT_NEAR(limit("rkmk4"), 2.0 * std::sqrt(2.0), 0.1);
  EXPECT_NEAR(limit("cf4"), 2.0 * std::sqrt(2.0), 0.1);
  EXPECT_NEAR(limit("splitting"), 2.0, 0.1);
  EXPECT_NEAR(limit("lgvi"), 2.0, 0.1);
}

TEST(StabilityStudy, ImplicitGeneralizedAlphaGoesFarBeyond) {
  EXPECT_GT(limit("genalpha"), 10.0);
}

TEST(StabilityStudy, CharacteristicFrequencyOfScenes) {
  EXPECT_DOUBLE_EQ(characteristicFrequency(loadScene("stiff-spring")), 100.0);
  EXPECT_DOUBLE_EQ(characteristicFrequency(loadScene("fast-top")), 1000.0);
}

}  // namespace
}  // namespace app
}  // namespace lieflow
