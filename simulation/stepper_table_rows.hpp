/// \file
/// The table of steppers (internal to joints/): one row per integrator of
/// integrators/registry.hpp, in its order, and in each row one factory per
/// system kind (simulation/stepper_table.hpp):
///
/// | row                  | single body | maximal          | joint tree  | joint, couplings | joint, loops |
/// |----------------------|-------------|------------------|-------------|------------------|--------------|
/// | rkmk-*, cg3, cf4     | stepper     | projected        | stepper     | projected        | projected    |
/// | rkmk45               | adaptive    | adaptive, proj.  | adaptive    | adaptive, proj.  | adaptive, p. |
/// | lgvi                 | Lgvi        | ConstrainedLgvi  | JointSpaceVariational (rows: RATTLE's multipliers) |
/// | splitting            | Splitting   | —                | —           | —                | —            |
/// | genalpha             | GenAlpha    | ConstrainedGenAlpha | GenAlpha | CoupledGenAlpha  | ConstrainedGenAlpha (dense) |
/// | radau5               | RadauIIA    | projected        | RadauIIA    | projected        | projected    |
/// | exact                | exact flow  | —                | —           | —                | —            |
///
/// "projected": the explicit stepper in index-1 form, projected onto the
/// constraints after every step (integrators/projected_stepper.hpp). A cell
/// without a stepper is `make(Kind)` returning NoStepper with the reason; a
/// row may add `covers(Kind, subject, why)` for what the scene must hold
/// (lgvi in joint coordinates: no prescribed motion; exact: no torque).
/// runStepper is the one place a name chooses a stepper; the queries of
/// stepper_table.hpp read the same rows.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "integrators/adaptive.hpp"
#include "integrators/butcher_tableau.hpp"
#include "integrators/commutator_free.hpp"
#include "integrators/constrained_generalized_alpha.hpp"
#include "integrators/constrained_lgvi.hpp"
#include "dynamics/rigid_body/exact_free_body.hpp"
#include "integrators/generalized_alpha.hpp"
#include "integrators/joint_space_variational.hpp"
#include "integrators/lgvi.hpp"
#include "integrators/projected_stepper.hpp"
#include "integrators/radau_iia.hpp"
#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "integrators/rkmk.hpp"
#include "integrators/splitting.hpp"
#include "dynamics/joint_space/articulated_coupled_alpha.hpp"
#include "dynamics/joint_space/articulated_kkt_assembly.hpp"
#include "dynamics/joint_space/articulated_system.hpp"
#include "dynamics/maximal/kkt_assembly.hpp"
#include "dynamics/maximal/multibody_system.hpp"
#include "simulation/simulation_observer.hpp"
#include "simulation/stepper_table.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace stepper_table {

/// The table's columns as types (a factory per column).
template <SystemKind K>
struct Column {
  static constexpr SystemKind kind = K;
};
using SingleBody = Column<SystemKind::kSingleBody>;
using Maximal = Column<SystemKind::kMaximal>;
using JointTree = Column<SystemKind::kJointTree>;
using JointCoupled = Column<SystemKind::kJointCoupled>;
using JointLoops = Column<SystemKind::kJointLoops>;

/// f(Column{}) for the column of `kind`: the one switch from a kind to its type.
template <typename F>
auto withColumn(SystemKind kind, F&& f) {
  switch (kind) {
    case SystemKind::kSingleBody: return f(SingleBody{});
    case SystemKind::kMaximal: return f(Maximal{});
    case SystemKind::kJointTree: return f(JointTree{});
    case SystemKind::kJointCoupled: return f(JointCoupled{});
    case SystemKind::kJointLoops: break;
  }
  return f(JointLoops{});
}

/// A cell without a stepper, and why.
struct NoStepper {
  const char* why;
};

/// The adaptive cell: rkmk45's stepper, run by integrateAdaptive, its
/// accepted states moved by `projection` (NoProjection without constraints).
template <typename Stepper, typename Projection>
struct AdaptiveRun {
  Stepper stepper;
  Projection projection;
};
template <typename Cell>
struct IsAdaptiveRun : std::false_type {};
template <typename Stepper, typename Projection>
struct IsAdaptiveRun<AdaptiveRun<Stepper, Projection>> : std::true_type {};

/// The run's option `key` or its default.
inline double option(const SimulationOptions& o, const std::string& key, double fallback) {
  return simulation_detail::option(o, key, fallback);
}

/// The positions and then the velocities onto the constraints (rkmk45's
/// projection after each accepted step and at each output).
template <typename System>
auto projectionOnto(const System& system) {
  return [&system, p = ProjectionOptions{}](double t, typename System::State* y, std::string* why) {
    int iterations = 0;
    return system.projectPositions(t, y, p.tolerance, p.max_iterations, &iterations, why) &&
           system.projectVelocities(t, y, why);
  };
}

/// A stepper as column K runs it: bare without constraints (a single body, a
/// tree in joint coordinates), projected onto them after every step
/// otherwise (the explicit rows and radau5).
template <typename K, typename Stepper>
auto bareOrProjected(K, Stepper stepper) {
  if constexpr (K::kind == SystemKind::kSingleBody || K::kind == SystemKind::kJointTree)
    return stepper;
  else
    return ProjectedStepper<Stepper>(std::move(stepper));
}

/// rkmk-euler, rkmk-heun, rkmk3, rkmk4, cg3, cf4: explicit steppers, bare
/// without constraints, projected with them. `Make<State>()` builds one.
template <typename Make>
struct ExplicitRow {
  const char* name;
  Make build;
  template <typename K, typename System>
  auto make(K kind, const System&, const typename System::State& y0, const SimulationOptions&) const {
    return bareOrProjected(kind, build(y0));
  }
};
template <typename Make>
ExplicitRow<Make> explicitRow(const char* name, Make build) {
  return {name, build};
}
/// A Runge–Kutta–Munthe-Kaas stepper of a tableau (its State from the tag).
inline auto rkmk(ButcherTableau (*tableau)()) {
  return [tableau](const auto& tag) { return RkmkStepper<std::decay_t<decltype(tag)>>(tableau()); };
}

struct Rkmk45Row {
  const char* name = "rkmk45";
  template <typename System, typename K>
  auto make(K, const System& system, const typename System::State&, const SimulationOptions&) const {
    using State = typename System::State;
    RkmkStepper<State> stepper(ButcherTableau::dormandPrince54());
    if constexpr (K::kind == SystemKind::kSingleBody || K::kind == SystemKind::kJointTree)
      return AdaptiveRun<RkmkStepper<State>, NoProjection>{std::move(stepper), {}};
    else
      return AdaptiveRun<RkmkStepper<State>, decltype(projectionOnto(system))>{std::move(stepper),
                                                                                  projectionOnto(system)};
  }
};

struct LgviRow {
  const char* name = "lgvi";
  template <typename System>
  auto make(SingleBody, const System&, const typename System::State&, const SimulationOptions& o) const {
    LgviOptions l;
    l.tolerance = option(o, "tolerance", l.tolerance);
    l.max_iterations = static_cast<int>(option(o, "max_iterations", l.max_iterations));
    // cayley = 1: the Cayley-map variant (no h‖ω‖ < 1 limit of the exp map).
    if (option(o, "cayley", 0.0) == 1.0) l.map = LgviMap::kCayley;
    return LgviStepper<typename System::State>(l);
  }
  /// RATTLE with the constraint impulses (integrators/constrained_lgvi.hpp).
  auto make(Maximal, const multibody::MultibodySystem&, const multibody::MultibodyGroupState&,
            const SimulationOptions& o) const {
    ConstrainedLgviOptions l;
    l.tolerance = option(o, "tolerance", l.tolerance);
    l.max_iterations = static_cast<int>(option(o, "max_iterations", l.max_iterations));
    if (option(o, "cayley", 0.0) == 1.0) l.rotation.map = LgviMap::kCayley;
    return ConstrainedLgviStepper<multibody::MultibodySystem>(l);
  }
  /// The variational integrator on the joints' groups, coupling rows, loops
  /// and gear rows as RATTLE's multipliers
  /// (integrators/joint_space_variational.hpp).
  template <typename K, typename = std::enable_if_t<K::kind != SystemKind::kSingleBody &&
                                                    K::kind != SystemKind::kMaximal>>
  auto make(K, const articulated::ArticulatedSystem&, const articulated::ArticulatedState&,
            const SimulationOptions& o) const {
    if (option(o, "cayley", 0.0) != 0.0)
      throw InvalidInput("cayley", "has no meaning in joint coordinates (lgvi there turns its rotations by exp)");
    JointSpaceVariationalOptions v;
    v.tolerance = option(o, "tolerance", v.tolerance);
    v.max_iterations = static_cast<int>(option(o, "max_iterations", v.max_iterations));
    return JointSpaceVariationalStepper<articulated::ArticulatedSystem>(v);
  }
  template <typename K, typename = std::enable_if_t<K::kind != SystemKind::kSingleBody &&
                                                    K::kind != SystemKind::kMaximal>>
  bool covers(K, const articulated::ArticulatedSystem& system, std::string* why) const {
    if (system.variationalCovers(why)) return true;
    if (why) *why = "'lgvi' cannot run this scene in joint coordinates: " + *why + " (run it with `formulation` maximal)";
    return false;
  }
};

struct SplittingRow {
  const char* name = "splitting";
  template <typename System>
  auto make(SingleBody, const System& system, const typename System::State&, const SimulationOptions&) const {
    return SplittingStepper<typename System::State>(system.inertia());
  }
  template <typename K, typename... Unused, typename = std::enable_if_t<K::kind != SystemKind::kSingleBody>>
  NoStepper make(K, const Unused&...) const {
    if (K::kind == SystemKind::kMaximal)
      return {"its sub-flows are each body's free rotation, which leaves the joints; the splitting that keeps "
              "them (kick, constrained drift, kick: RATTLE) is lgvi"};
    return {"splitting is written for bodies in maximal coordinates"};
  }
};

struct GenalphaRow {
  const char* name = "genalpha";
  static GeneralizedAlphaOptions options(const SimulationOptions& o) {
    GeneralizedAlphaOptions g;
    g.rho_inf = option(o, "rho_inf", g.rho_inf);
    g.tolerance = option(o, "tolerance", g.tolerance);
    g.max_iterations = static_cast<int>(option(o, "max_iterations", g.max_iterations));
    return g;
  }
  /// Without constraints (`index` chooses a constrained formulation: it has
  /// nothing to choose here).
  template <typename System, typename K,
            typename = std::enable_if_t<K::kind == SystemKind::kSingleBody || K::kind == SystemKind::kJointTree>>
  auto make(K, const System&, const typename System::State&, const SimulationOptions& o) const {
    return GeneralizedAlphaStepper<typename System::State>(options(o));
  }
  static ConstrainedGeneralizedAlphaOptions constrainedOptions(const SimulationOptions& o) {
    ConstrainedGeneralizedAlphaOptions g;
    g.rho_inf = option(o, "rho_inf", g.rho_inf);
    g.tolerance = option(o, "tolerance", g.tolerance);
    g.max_iterations = static_cast<int>(option(o, "max_iterations", g.max_iterations));
    g.index = static_cast<int>(option(o, "index", g.index));
    return g;
  }
  auto make(Maximal, const multibody::MultibodySystem&, const multibody::MultibodyGroupState&,
            const SimulationOptions& o) const {
    return ConstrainedGeneralizedAlphaStepper<multibody::MultibodySystem>(constrainedOptions(o));
  }
  /// In an orthonormal basis of the coupling rows' kernel
  /// (dynamics/joint_space/articulated_coupled_alpha.hpp).
  auto make(JointCoupled, const articulated::ArticulatedSystem& system, const articulated::ArticulatedState&,
            const SimulationOptions& o) const {
    return articulated::CoupledGeneralizedAlphaStepper(system, system.couplingRows(), options(o));
  }
  /// Loops and gear rows on multipliers, the dense iteration matrix of
  /// dynamics/joint_space/articulated_kkt_assembly.hpp.
  auto make(JointLoops, const articulated::ArticulatedSystem&, const articulated::ArticulatedState&,
            const SimulationOptions& o) const {
    return ConstrainedGeneralizedAlphaStepper<articulated::ArticulatedSystem>(constrainedOptions(o));
  }
  /// Measured: the four-bar converges at order 2 with 1-2 Newton iterations
  /// per step (3.2x faster than maximal coordinates), but on the built-in
  /// slider-crank the default rho_inf = 1 stops at t = 8.1, 10.1, 11.8 and
  /// 13.9 s for h = 4, 2, 1 and 0.5 ms: a period-2 oscillation of the
  /// multipliers grows, in bursts (its amplitude in the weld's force about
  /// 1e-3 N at 1 s, 2e-2 N at 5 s, 0.4 N at 8 s at h = 2 ms), and the time
  /// it takes depends weakly on the step, so its growth per step shrinks
  /// about as h. That points to the spurious root of the generalized-alpha
  /// recurrence (G3), at exactly -1 when rho_inf = 1, pushed off the unit
  /// circle by O(h) terms. It is not the held mid-step Jacobian
  /// (J(q_n) alone, or J-bar updated every iteration, stop at the same
  /// times), not P's mass matrix (P = J-bar^T stops the same), nor the rows'
  /// conditioning (their singular values stay within 0.28-1.0). A likely
  /// source, not proven: in joint coordinates M(q) varies, so the Coriolis
  /// tangent has the indefinite symmetric part M'/2 (negative damping part of
  /// the time), where maximal coordinates' body-frame M is constant. Any
  /// damping of that root runs it: rho_inf = 0.99 runs 30 s at h = 4, 1 and
  /// 0.5 ms (1.36-2.0 Newton iterations per step), as index 3 at rho_inf =
  /// 0.9 does. The default keeps rho_inf = 1 and maximal coordinates there.
  const char* notDefault(JointLoops) const {
    return "genalpha at rho_inf = 1 (no numerical damping) in joint coordinates stops on some loops where maximal "
           "coordinates run (the slider-crank after 8-14 s: a period-2 mode of the multipliers grows; "
           "`options` rho_inf=0.99 runs it)";
  }
  bool covers(JointLoops, const articulated::ArticulatedSystem& system, std::string* why) const {
    std::string reason;
    if (!system.hasPrescribedCoordinate("genalpha", &reason)) {
      if (system.closureRowsIndependent()) return true;
      reason = "its loops repeat rows in joint coordinates (the tree's joints already hold them), which "
               "genalpha's iteration matrix cannot take";
    }
    if (why) *why = "'genalpha' cannot run this scene in joint coordinates: " + reason + " (run it with `formulation` maximal)";
    return false;
  }
};

/// The exact flow sampled on the output grid (a "step" is one evaluation).
struct ExactStepper {
  std::shared_ptr<const ExactFreeRigidBody> flow;
  template <typename System, typename State>
  State step(const System& system, double t, const State& y, double h, StepReport*) const {
    State next = y;
    Eigen::Quaterniond q;
    flow->evaluate(t + h, &q, &next.omega);
    next.R = SO3d(q);
    advanceTranslation(system, t, h, &next);
    return next;
  }
  static void advanceTranslation(const RotorSystem<double>&, double, double, RotorState<double>*) {}
  static void advanceTranslation(const FreeBodySystem<double>& sys, double t, double h, FreeBodyState<double>* y) {
    // Constant force (gravity): exact parabola.
    const Eigen::Vector3d a = sys.force(t) / sys.mass();
    y->p += h * y->v + 0.5 * h * h * a;
    y->v += h * a;
  }
};

/// radau5 (integrators/radau_iia.hpp), bare or projected as the explicit rows.
struct RadauRow {
  const char* name = "radau5";
  static RadauOptions options(const SimulationOptions& o) {
    RadauOptions r;
    r.tolerance = option(o, "tolerance", r.tolerance);
    r.max_iterations = static_cast<int>(option(o, "max_iterations", r.max_iterations));
    r.jacobian_reuse = option(o, "jacobian_reuse", r.jacobian_reuse);
    return r;
  }
  template <typename K, typename System>
  auto make(K kind, const System&, const typename System::State&, const SimulationOptions& o) const {
    return bareOrProjected(kind, RadauIIAStepper<typename System::State>(options(o)));
  }
};

struct ExactRow {
  const char* name = "exact";
  template <typename System>
  auto make(SingleBody, const System& system, const typename System::State& y0, const SimulationOptions&) const {
    return ExactStepper{std::make_shared<const ExactFreeRigidBody>(system.inertia(), y0.R.quaternion(), y0.omega)};
  }
  template <typename K, typename... Unused, typename = std::enable_if_t<K::kind != SystemKind::kSingleBody>>
  NoStepper make(K, const Unused&...) const {
    return {"the exact flow is a torque-free single body's"};
  }
  bool covers(SingleBody, const RigidBodyParameters<double>& p, std::string* why) const {
    if (!p.has_pivot && p.spring_stiffness == 0.0 && !p.torque_body) return true;
    if (why)
      *why = std::string("'exact' is the torque-free flow: this scene has ") +
             (p.has_pivot ? "a pivot under gravity" : "a torque on the body");
    return false;
  }
};

/// The rows, in the registry's order (tests/app/stepper_table_test.cpp
/// checks that the names match).
inline const auto& rows() {
  static const auto table = std::make_tuple(
      explicitRow("rkmk-euler", rkmk(&ButcherTableau::euler)), explicitRow("rkmk-heun", rkmk(&ButcherTableau::heun)),
      explicitRow("rkmk3", rkmk(&ButcherTableau::kutta3)), explicitRow("rkmk4", rkmk(&ButcherTableau::rk4)),
      explicitRow("rkmk6", rkmk(&ButcherTableau::butcher6)),
      Rkmk45Row{},
      explicitRow("cg3", [](const auto& tag) { return CrouchGrossman3Stepper<std::decay_t<decltype(tag)>>(); }),
      explicitRow("cf4", [](const auto& tag) { return CommutatorFree4Stepper<std::decay_t<decltype(tag)>>(); }),
      LgviRow{}, SplittingRow{}, GenalphaRow{}, RadauRow{}, ExactRow{});
  return table;
}

/// Calls f(row) on every row, in order.
template <typename F>
void forEachRow(F&& f) {
  std::apply([&](const auto&... row) { (f(row), ...); }, rows());
}

/// Whether the row's cell for column K is empty (NoStepper, callable without a system).
template <typename Row, typename K, typename = void>
struct IsEmptyCell : std::false_type {};
template <typename Row, typename K>
struct IsEmptyCell<Row, K, std::void_t<decltype(std::declval<const Row&>().make(K{}))>> : std::true_type {};

/// Whether the row's cell for column K runs only when asked for
/// (`notDefault(K)` returns why).
template <typename Row, typename K, typename = void>
struct HasNotDefault : std::false_type {};
template <typename Row, typename K>
struct HasNotDefault<Row, K, std::void_t<decltype(std::declval<const Row&>().notDefault(K{}))>> : std::true_type {};

/// Whether the row says what a scene must hold in column K.
template <typename Row, typename K, typename Subject, typename = void>
struct HasCovers : std::false_type {};
template <typename Row, typename K, typename Subject>
struct HasCovers<Row, K, Subject,
                 std::void_t<decltype(std::declval<const Row&>().covers(K{}, std::declval<const Subject&>(),
                                                                        static_cast<std::string*>(nullptr)))>>
    : std::true_type {};

/// Whether the integrator named covers the scene behind `subject` in column
/// K (true where its row asks nothing; false with `why` where it does not).
template <typename K, typename Subject>
bool covers(const std::string& integrator, const Subject& subject, std::string* why) {
  bool result = true;
  forEachRow([&](const auto& row) {
    using Row = std::decay_t<decltype(row)>;
    if constexpr (HasCovers<Row, K, Subject>::value)
      if (integrator == row.name) result = row.covers(K{}, subject, why);
  });
  return result;
}

/// Runs the integrator `o.integrator` names on `system` from y0 in column K:
/// a fixed-step stepper through runFixedStep, rkmk45 through
/// integrateAdaptive. The one place where a name chooses a stepper.
template <typename K, typename System>
SimulationResult runStepper(K, const Simulation::Model& model, const System& system, const typename System::State& y0,
                            const SimulationOptions& o, const std::vector<std::string>& columns,
                            const std::function<void(const std::vector<double>&)>& row_sink) {
  std::optional<SimulationResult> result;
  forEachRow([&](const auto& row) {
    if (result || o.integrator != row.name) return;
    auto cell = row.make(K{}, system, y0, o);
    using Cell = decltype(cell);
    if constexpr (std::is_same_v<Cell, NoStepper>) {
      throw InvalidInput("`integrator`", std::string(cell.why));
    } else if constexpr (IsAdaptiveRun<Cell>::value) {
      AdaptiveOptions a;
      a.rtol = option(o, "rtol", a.rtol);
      a.atol = option(o, "atol", a.atol);
      a.max_steps = o.max_steps;
      a.heartbeat = o.progress;
      result = simulation_detail::observeRun(
          model, system, o, stepCount(0.0, o.t_end, o.dt), columns, row_sink,
          [&](auto& observer) {
            return integrateAdaptive(cell.stepper, system, y0, 0.0, o.t_end, o.dt, a, observer, cell.projection);
          });
    } else {
      result = simulation_detail::runFixedStep(model, system, y0, o, columns, row_sink, std::move(cell));
    }
  });
  if (!result) throw InvalidInput("`integrator`", "unknown integrator '" + o.integrator + "'");
  return *result;
}

}  // namespace stepper_table
}  // namespace lieflow
