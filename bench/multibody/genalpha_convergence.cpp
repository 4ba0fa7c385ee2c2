// study_genalpha_convergence: the errors of the Lie-group generalized-α step
// with joints at t = 0.5 s against a projected RK4 reference (h = 1e-4, λ
// from the index-1 equations at its final state), on the three-link chain of
// tests/joints/stabilized_genalpha_test.cpp (randomRevoluteChain(3, seed 7)),
// for the stabilized index-2 form and index 3 at ρ∞ = 1 and 0.8 and h from
// 0.02 down to 0.000625. Writes CSV to stdout:
//   index,rho_inf,h,steps,newton_iterations_mean,error_q,error_u,error_lambda
// error_q: max over the bodies of |Δp| [m] and of the rotation angle of
// R_refᵀ R [rad]; error_u: max |Δu|; error_lambda: max |Δλ| / max |λ_ref|.
// A failed run is a row with its errors empty and the reason on stderr.
// papers/genalpha-index2/reproduce.sh runs it and plots the figure.
#include <algorithm>
#include <cstdio>
#include <string>

#include "integrators/butcher_tableau.hpp"
#include "integrators/constrained_generalized_alpha.hpp"
#include "integrators/integrate.hpp"
#include "integrators/projected_stepper.hpp"
#include "integrators/rkmk.hpp"
#include "joints/multibody/chain_builder.hpp"
#include "joints/multibody/kkt_assembly.hpp"
#include "joints/multibody/multibody_system.hpp"

int main() {
  using namespace lieflow;             // NOLINT: a one-purpose program
  using namespace lieflow::multibody;  // NOLINT
  MultibodyState s0;
  const Eigen::Matrix3d I = Eigen::Vector3d(0.002, 0.01, 0.012).asDiagonal();
  const MultibodySystem system(randomRevoluteChain(3, true, I, 7, &s0), {});
  const MultibodyGroupState y0 = system.makeState(s0);
  const double T = 0.5;

  ProjectedStepper<RkmkStepper<MultibodyGroupState>> rk4(RkmkStepper<MultibodyGroupState>(ButcherTableau::rk4()));
  MultibodyGroupState ref = y0;
  const RunSummary rr = integrateFixedStep(rk4, system, y0, 0.0, T, 1e-4, [&](long, double, const MultibodyGroupState& s) {
    ref = s;
    return true;
  });
  Eigen::VectorXd udot_ref, lambda_ref;
  std::string why;
  if (rr.failed || !system.accelerations(T, ref, &udot_ref, &lambda_ref, &why)) {
    std::fprintf(stderr, "study_genalpha_convergence: the reference failed: %s%s\n", rr.failure.c_str(), why.c_str());
    return 1;
  }
  std::printf("index,rho_inf,h,steps,newton_iterations_mean,error_q,error_u,error_lambda\n");
  for (int index : {2, 3})
    for (double rho : {1.0, 0.8})
      for (double h : {0.02, 0.01, 0.005, 0.0025, 0.00125, 0.000625}) {
        ConstrainedGeneralizedAlphaOptions o;
        o.index = index;
        o.rho_inf = rho;
        o.tolerance = 1e-12;
        ConstrainedGeneralizedAlphaStepper<MultibodySystem> stepper(o);
        MultibodyGroupState y = y0;
        const RunSummary r = integrateFixedStep(stepper, system, y0, 0.0, T, h, [&](long, double, const MultibodyGroupState& s) {
          y = s;
          return true;
        });
        if (r.failed) {
          std::fprintf(stderr, "index %d, rho_inf %g, h %g: %s\n", index, rho, h, r.failure.c_str());
          std::printf("%d,%g,%g,%ld,,,,\n", index, rho, h, r.steps);
          continue;
        }
        double eq = 0.0;
        for (std::size_t i = 0; i < y.bodies.poses.size(); ++i) {
          eq = std::max(eq, (y.bodies.poses[i].p - ref.bodies.poses[i].p).norm());
          eq = std::max(eq, (ref.bodies.poses[i].R.inverse() * y.bodies.poses[i].R).log().norm());
        }
        const double eu = (y.velocities() - ref.velocities()).lpNorm<Eigen::Infinity>();
        const double el = (stepper.multipliers() - lambda_ref).lpNorm<Eigen::Infinity>() /
                          lambda_ref.lpNorm<Eigen::Infinity>();
        std::printf("%d,%g,%g,%ld,%.4f,%.6e,%.6e,%.6e\n", index, rho, h, r.steps, r.newtonIterationsMean(), eq, eu, el);
      }
  return 0;
}
