// study_genalpha_convergence: the errors of the Lie-group generalized-α step
// with joints at t = 0.5 s against a projected RK4 reference (h = 1e-4, λ
// from the index-1 equations at its final state), on the three-link chain of
// tests/simulation/stabilized_genalpha_test.cpp (three_link_convergence.hpp),
// for the stabilized index-2 form and index 3 at ρ∞ = 1 and 0.8 and h from
// 0.02 down to 0.000625. Writes CSV to stdout:
//   index,rho_inf,h,steps,newton_iterations_mean,error_q,error_u,error_lambda
// error_q: max over the bodies of |Δp| [m] and of the rotation angle of
// R_refᵀ R [rad]; error_u: max |Δu|; error_lambda: max |Δλ| / max |λ_ref|.
// A failed run is a row with its errors empty and the reason on stderr.
// papers/genalpha-index2/reproduce.sh runs it and plots the figure.
#include <cstdio>

#include "bench/multibody/three_link_convergence.hpp"
#include "integrators/constrained_generalized_alpha.hpp"
#include "integrators/integrate.hpp"
#include "dynamics/maximal/kkt_assembly.hpp"

int main() {
  using namespace lieflow;             // NOLINT: a one-purpose program
  using namespace lieflow::multibody;  // NOLINT
  const bench::ThreeLinkConvergence c;
  if (!c.ok) {
    std::fprintf(stderr, "study_genalpha_convergence: the reference failed: %s\n", c.why.c_str());
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
        MultibodyGroupState y = c.y0;
        const RunSummary r = integrateFixedStep(stepper, c.system, c.y0, 0.0, c.kEnd, h,
                                                [&](long, double, const MultibodyGroupState& s) {
                                                  y = s;
                                                  return true;
                                                });
        if (r.failed) {
          std::fprintf(stderr, "index %d, rho_inf %g, h %g: %s\n", index, rho, h, r.failure.c_str());
          std::printf("%d,%g,%g,%ld,,,,\n", index, rho, h, r.steps);
          continue;
        }
        const auto e = c.errors(y, stepper.multipliers());
        std::printf("%d,%g,%g,%ld,%.4f,%.6e,%.6e,%.6e\n", index, rho, h, r.steps, r.newtonIterationsMean(), e.q, e.u,
                    e.lambda);
      }
  return 0;
}
