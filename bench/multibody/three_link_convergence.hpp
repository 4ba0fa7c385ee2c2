/// \file
/// The convergence case shared by tests/simulation/stabilized_genalpha_test.cpp
/// and study_genalpha_convergence (papers/genalpha-index2/): the three-link
/// random revolute chain (chain_builder.hpp, seed 7) over t ∈ [0, 0.5 s], its
/// reference by projected RK4 at h = 1e-4 with λ from the index-1 equations at
/// the final state, and the errors of a final state against it.
#pragma once

#include <algorithm>
#include <string>

#include "integrators/butcher_tableau.hpp"
#include "integrators/integrate.hpp"
#include "integrators/projected_stepper.hpp"
#include "integrators/rkmk.hpp"
#include "dynamics/maximal/chain_builder.hpp"
#include "dynamics/maximal/multibody_system.hpp"

namespace lieflow {
namespace bench {

class ThreeLinkConvergence {
  multibody::MultibodyState s0_;  // first: chain() fills it before system is built

 public:
  static constexpr double kEnd = 0.5;        ///< final time [s]
  static constexpr double kReferenceStep = 1e-4;

  multibody::MultibodySystem system;
  multibody::MultibodyGroupState y0;
  multibody::MultibodyGroupState reference;  ///< at kEnd
  Eigen::VectorXd lambda_reference;
  bool ok = false;
  std::string why;  ///< when !ok: why the reference failed

  ThreeLinkConvergence() : system(chain(&s0_), {}), y0(system.makeState(s0_)), reference(y0) {
    ProjectedStepper<RkmkStepper<multibody::MultibodyGroupState>> rk4{
        RkmkStepper<multibody::MultibodyGroupState>(ButcherTableau::rk4())};
    const RunSummary r = integrateFixedStep(rk4, system, y0, 0.0, kEnd, kReferenceStep,
                                            [&](long, double, const multibody::MultibodyGroupState& s) {
                                              reference = s;
                                              return true;
                                            });
    Eigen::VectorXd udot;
    ok = !r.failed && system.accelerations(kEnd, reference, &udot, &lambda_reference, &why);
    if (r.failed) why = r.failure;
  }

  /// Errors at kEnd: positions (max over the bodies of |Δp| [m] and of the
  /// rotation angle of R_refᵀ R [rad]), velocities (max |Δu|) and
  /// multipliers (max |Δλ| / max |λ_ref|).
  struct Errors {
    double q = 0.0, u = 0.0, lambda = 0.0;
  };
  Errors errors(const multibody::MultibodyGroupState& y, const Eigen::VectorXd& lambda) const {
    Errors e;
    for (std::size_t i = 0; i < y.bodies.poses.size(); ++i) {
      e.q = std::max(e.q, (y.bodies.poses[i].p - reference.bodies.poses[i].p).norm());
      e.q = std::max(e.q, (reference.bodies.poses[i].R.inverse() * y.bodies.poses[i].R).log().norm());
    }
    e.u = (y.velocities() - reference.velocities()).lpNorm<Eigen::Infinity>();
    e.lambda = (lambda - lambda_reference).lpNorm<Eigen::Infinity>() / lambda_reference.lpNorm<Eigen::Infinity>();
    return e;
  }

 private:
  static multibody::MultibodyModel chain(multibody::MultibodyState* s0) {
    const Eigen::Matrix3d I = Eigen::Vector3d(0.002, 0.01, 0.012).asDiagonal();
    return multibody::randomRevoluteChain(3, true, I, 7, s0);
  }
};

}  // namespace bench
}  // namespace lieflow
