/// \file
/// Observing a run (internal to joints/): the CSV rows of each system's
/// state, energy and momentum drift, the scene's invariants, non-finite and
/// blow-up detection, and observeRun, which wraps a stepping loop with them.
#pragma once

#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "integrators/integrate.hpp"
#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "simulation/progress_pacer.hpp"
#include "simulation/simulation_model.hpp"

namespace lieflow {
namespace simulation_detail {

/// Appends the body columns of a rotor/free-body state to a row.
inline void appendBody(const Simulation::Model& m, const SO3d& R, const Eigen::Vector3d& omega,
                const Eigen::Vector3d& p, const Eigen::Vector3d& v, std::vector<double>* row) {
  const Eigen::Quaterniond& q = R.quaternion();
  row->insert(row->end(), {q.w(), q.x(), q.y(), q.z(), omega.x(), omega.y(), omega.z()});
  if (m.translational_output) row->insert(row->end(), {p.x(), p.y(), p.z(), v.x(), v.y(), v.z()});
}

/// Appends an accelerometer's reading at the point s (body axes, from the
/// centre of mass) of a body with orientation R, angular velocity ω and
/// acceleration ω̇ (body axes), centre-of-mass acceleration a_c (world):
///   f = Rᵀ(a_s − g) = Rᵀ(a_c − g) + ω̇ × s + ω × (ω × s)
/// (the specific force, gravity included: at rest it reads −Rᵀg).
inline void appendSpecificForce(const Eigen::Matrix3d& R, const Eigen::Vector3d& omega,
                                const Eigen::Vector3d& omega_dot, const Eigen::Vector3d& a_c,
                                const Eigen::Vector3d& gravity, const Eigen::Vector3d& s, std::vector<double>* row) {
  const Eigen::Vector3d f = R.transpose() * (a_c - gravity) + omega_dot.cross(s) + omega.cross(omega.cross(s));
  row->insert(row->end(), {f.x(), f.y(), f.z()});
}

struct RowBuilder {
  const Simulation::Model& model;
  /// Rows carry B.ax, B.ay, B.az (SimulationOptions::imu).
  bool imu = false;

  RowBuilder(const Simulation::Model& m, bool with_imu) : model(m), imu(with_imu) {}

  void operator()(const RotorSystem<double>& sys, double t, const RotorState<double>& y,
                  std::vector<double>* row) const {
    row->clear();
    row->push_back(t);
    Eigen::Vector3d p = model.fixed_position, v = Eigen::Vector3d::Zero();
    if (model.params.has_pivot) {
      p = model.params.pivot_world + y.R * model.params.com_from_pivot;
      v = y.R * y.omega.cross(model.params.com_from_pivot);
    }
    appendBody(model, y.R, y.omega, p, v, row);
    if (imu) {
      // About a pivot the centre of mass turns on a sphere; a free rotor's is held.
      typename RotorState<double>::Tangent F;
      sys.velocity(t, y, &F);
      const Eigen::Vector3d wdot = F.tail<3>(), r = model.params.com_from_pivot;
      const Eigen::Vector3d a_c = model.params.has_pivot
                                      ? Eigen::Vector3d(y.R * (wdot.cross(r) + y.omega.cross(y.omega.cross(r))))
                                      : Eigen::Vector3d::Zero();
      appendSpecificForce(y.R.matrix(), y.omega, wdot, a_c, model.gravity, model.sensors[0], row);
    }
    const Eigen::Vector3d L = sys.spatialAngularMomentum(y);
    row->insert(row->end(), {sys.energy(t, y), L.x(), L.y(), L.z(), 0.0});
  }

  void operator()(const FreeBodySystem<double>& sys, double t, const FreeBodyState<double>& y,
                  std::vector<double>* row) const {
    row->clear();
    row->push_back(t);
    appendBody(model, y.R, y.omega, y.p, y.v, row);
    if (imu) {
      typename FreeBodyState<double>::Tangent F;
      sys.velocity(t, y, &F);
      appendSpecificForce(y.R.matrix(), y.omega, F.segment<3>(9), F.segment<3>(6), model.gravity, model.sensors[0],
                          row);
    }
    const Eigen::Vector3d L = sys.spatialAngularMomentum(y);
    row->insert(row->end(), {sys.energy(t, y), L.x(), L.y(), L.z(), 0.0});
  }

  void operator()(const multibody::MultibodySystem& sys, double t, const multibody::MultibodyGroupState& y,
                  std::vector<double>* row) const {
    row->clear();
    row->push_back(t);
    // u̇ per body: (v̇ world, ω̇ body), or ω̇ for a rotation-only body.
    if (imu) sys.velocity(t, y, &field);
    const int n = static_cast<int>(field.size()) / 2;
    for (int i = 0; i < sys.bodyCount(); ++i) {
      const auto& P = y.bodies.poses[i];
      const auto& V = y.bodies.velocities[i];
      const Eigen::Quaterniond& q = P.R.quaternion();
      row->insert(row->end(), {q.w(), q.x(), q.y(), q.z(), V.omega.x(), V.omega.y(), V.omega.z()});
      if (!sys.rotationOnly(i))
        row->insert(row->end(), {P.p.x(), P.p.y(), P.p.z(), V.v.x(), V.v.y(), V.v.z()});
      if (imu) {
        const int o = n + sys.dofBegin(i);
        const bool rot = sys.rotationOnly(i);
        const Eigen::Vector3d a_c = rot ? Eigen::Vector3d::Zero() : Eigen::Vector3d(field.segment<3>(o));
        appendSpecificForce(P.R.matrix(), V.omega, field.segment<3>(o + (rot ? 0 : 3)), a_c, model.gravity,
                            model.sensors[i], row);
      }
    }
    for (const JointOutput& o : sys.jointOutputs(t, y)) {
      if (o.coordinates == 1) row->insert(row->end(), {o.phi[0], o.phidot[0], o.moment[0]});
      if (o.coordinates == 2)
        row->insert(row->end(), {o.phi[0], o.phi[1], o.phidot[0], o.phidot[1], o.moment[0], o.moment[1]});
      if (o.coordinates == 3)
        row->insert(row->end(), {o.phi[0], o.phi[1], o.phi[2], o.phidot[0], o.phidot[1], o.phidot[2], o.moment[0],
                                 o.moment[1], o.moment[2]});
      if (o.kind == JointKind::kFixed) row->insert(row->end(), o.reaction.data(), o.reaction.data() + 6);
    }
    const Eigen::Vector3d L = sys.angularMomentum(y);
    row->insert(row->end(), {sys.energy(y), L.x(), L.y(), L.z(), sys.constraintError(t, y)});
  }

  /// Joint coordinates: the same columns, bodies and joints in scene order;
  /// the tree's joints hold by construction, constraint_error is the loops'
  /// (0 without loops).
  void operator()(const articulated::ArticulatedSystem& sys, double t, const articulated::ArticulatedState& y,
                  std::vector<double>* row) const {
    row->clear();
    row->push_back(t);
    sys.jointOutputs(t, y, &joint_outputs);  // also leaves the kinematics at (t, y)
    const std::vector<int>& tree = sys.model().tree_index;
    for (std::size_t b = 0; b < tree.size(); ++b) {
      const int i = tree[b];
      // The quaternion of R with the sign nearest the last row's (the scene's
      // at t = 0), so that a column does not jump between q and −q.
      Eigen::Quaterniond q(sys.rotation(i));
      if (last_quaternions.size() != tree.size()) {
        last_quaternions.clear();
        for (std::size_t k = 0; k < tree.size(); ++k)
          last_quaternions.push_back(sys.model().bodies[tree[k]].initial_orientation);
      }
      if (q.coeffs().dot(last_quaternions[b].coeffs()) < 0.0) q.coeffs() = -q.coeffs();
      last_quaternions[b] = q;
      const Eigen::Vector3d w = sys.angularVelocityBody(i), p = sys.centreOfMass(i), v = sys.velocityOfCentre(i);
      row->insert(row->end(), {q.w(), q.x(), q.y(), q.z(), w.x(), w.y(), w.z()});
      if (!sys.model().bodies[i].rotation_only)
        row->insert(row->end(), {p.x(), p.y(), p.z(), v.x(), v.y(), v.z()});
      if (imu)
        appendSpecificForce(sys.rotation(i), w, sys.angularAccelerationBody(i), sys.accelerationOfCentre(i),
                            model.gravity, model.sensors[b], row);
    }
    for (const articulated::ArticulatedJointOutput& o : joint_outputs) {
      if (o.coordinates == 1) row->insert(row->end(), {o.phi[0], o.phidot[0], o.moment[0]});
      if (o.coordinates == 2)
        row->insert(row->end(), {o.phi[0], o.phi[1], o.phidot[0], o.phidot[1], o.moment[0], o.moment[1]});
      if (o.coordinates == 3)
        row->insert(row->end(), {o.phi[0], o.phi[1], o.phi[2], o.phidot[0], o.phidot[1], o.phidot[2], o.moment[0],
                                 o.moment[1], o.moment[2]});
      if (o.welded) row->insert(row->end(), o.reaction.begin(), o.reaction.end());
    }
    const Eigen::Vector3d L = sys.angularMomentum(t, y);
    row->insert(row->end(), {sys.energy(t, y), L.x(), L.y(), L.z(), sys.constraintError(t, y)});
  }

  mutable std::vector<articulated::ArticulatedJointOutput> joint_outputs;
  mutable Eigen::VectorXd field;
  mutable std::vector<Eigen::Quaterniond> last_quaternions;
};

/// The spatial angular momentum about the world origin of a state.
template <typename System, typename State>
Eigen::Vector3d momentumOf(const System& sys, double, const State& y) {
  return sys.spatialAngularMomentum(y);
}
inline Eigen::Vector3d momentumOf(const articulated::ArticulatedSystem& sys, double t,
                                  const articulated::ArticulatedState& y) {
  return sys.angularMomentum(t, y);
}

/// Position-level constraint error of a state (0 for single-body systems,
/// whose joint is built into the system).
template <typename System, typename State>
double constraintErrorOf(const System&, double, const State&) {
  return 0.0;
}
inline double constraintErrorOf(const multibody::MultibodySystem& sys, double t,
                                const multibody::MultibodyGroupState& y) {
  return sys.constraintError(t, y);
}
inline double constraintErrorOf(const articulated::ArticulatedSystem& sys, double t,
                                const articulated::ArticulatedState& y) {
  return sys.constraintError(t, y);
}

/// The sum of the magnitudes of the energy's terms, the scale of its
/// round-off: the systems of joints sum kinetic, gravitational and spring
/// terms of opposite signs; a single body's energy is its scale.
template <typename System, typename State>
double energyTermScaleOf(const System& sys, double t, const State& y) {
  return std::abs(sys.energy(t, y));
}
inline double energyTermScaleOf(const multibody::MultibodySystem& sys, double,
                                const multibody::MultibodyGroupState& y) {
  return sys.energyTermScale(y);
}
inline double energyTermScaleOf(const articulated::ArticulatedSystem& sys, double t,
                                const articulated::ArticulatedState& y) {
  return sys.energyTermScale(t, y);
}

/// An initial energy below this fraction of its terms' magnitudes
/// (energyTermScaleOf) is round-off of a sum that is zero (a pendulum
/// released level with its pivot, cos(π/2) = 6e-17): the drift is then
/// absolute, in joules, as for E₀ = 0.
inline constexpr double kEnergyRoundOff = 1e-12;

/// An energy error this many times the initial energy means the run has
/// blown up, even while the state is still finite (an explicit method beyond
/// its stability limit can take thousands of steps to overflow).
inline constexpr double kBlowUpEnergyGrowth = 1e8;

/// Tracks energy and momentum drift over the observed states. The drifts are
/// relative to |E₀| and ‖L₀‖ (relativeDrift, invariants.hpp); when E₀ (or L₀)
/// is zero or near it — a body at rest at zero potential, or E₀ within
/// round-off of its terms (kEnergyRoundOff) — there is no scale and the
/// drift is absolute.
struct DriftTracker {
  bool momentum_conserved = false;
  double e0 = 0.0;       ///< the initial energy, 0 when it is round-off of its terms
  double e_start = 0.0;  ///< the initial energy as computed
  Eigen::Vector3d L0 = Eigen::Vector3d::Zero();
  double energy_drift = 0.0;
  double momentum_drift = 0.0;


  template <typename System, typename State>
  void observe(const System& sys, long k, double t, const State& y) {
    const double e = sys.energy(t, y);
    const Eigen::Vector3d L = momentumOf(sys, t, y);
    if (k == 0) {
      e0 = std::abs(e) > kEnergyRoundOff * energyTermScaleOf(sys, t, y) ? e : 0.0;
      e_start = e;
      L0 = L;
      return;
    }
    energy_drift = std::max(energy_drift, relativeDrift(std::abs(e - e_start), e0));
    if (momentum_conserved) momentum_drift = std::max(momentum_drift, relativeDrift((L - L0).norm(), L0.norm()));
  }

  /// The energy-growth blow-up test needs a scale: it is off when E₀ is zero
  /// or near it.
  bool blownUp() const { return std::abs(e0) > kNearZeroScale && energy_drift > kBlowUpEnergyGrowth; }
};

inline double option(const SimulationOptions& o, const std::string& key, double fallback) {
  const auto it = o.integrator_options.find(key);
  return it == o.integrator_options.end() ? fallback : it->second;
}

/// Feeds a state to the scene's invariants.
inline void observeInvariants(InvariantSet* set, const RotorSystem<double>&, const RotorState<double>& y) {
  set->observe(y.R, y.omega);
}
inline void observeInvariants(InvariantSet* set, const FreeBodySystem<double>&, const FreeBodyState<double>& y) {
  set->observe(y.R, y.omega);
}
inline void observeInvariants(InvariantSet* set, const multibody::MultibodySystem& sys,
                              const multibody::MultibodyGroupState& y, double t) {
  InvariantSet::MultibodyValues v;
  v.L = sys.angularMomentum(y);
  if (set->needsMultibodyValues()) {
    v.L_com = sys.centreOfMassMomentum(y);
    v.energy = sys.energy(y);
  }
  set->observe(t, v);
}
inline void observeInvariants(InvariantSet* set, const articulated::ArticulatedSystem& sys,
                              const articulated::ArticulatedState& y, double t) {
  InvariantSet::MultibodyValues v;
  v.L = sys.angularMomentum(t, y);
  if (set->needsMultibodyValues()) {
    v.L_com = sys.centreOfMassMomentum(t, y);
    v.energy = sys.energy(t, y);
  }
  set->observe(t, v);
}
template <typename System, typename State>
void observeInvariants(InvariantSet* set, const System& sys, const State& y, double) {
  observeInvariants(set, sys, y);
}

/// The dashpots' power Σ c φ̇² of a state (single bodies have none).
template <typename System, typename State>
double dissipatedPowerOf(const System&, double, const State&) {
  return 0.0;
}
inline double dissipatedPowerOf(const multibody::MultibodySystem& sys, double, const multibody::MultibodyGroupState& y) {
  return sys.dissipatedPower(y);
}
inline double dissipatedPowerOf(const articulated::ArticulatedSystem& sys, double t,
                                const articulated::ArticulatedState& y) {
  return sys.dissipatedPower(t, y);
}

/// Index of the first non-finite value of a row, or −1.
inline long firstNonFinite(const std::vector<double>& row) {
  for (std::size_t i = 0; i < row.size(); ++i)
    if (!std::isfinite(row[i])) return static_cast<long>(i);
  return -1;
}

/// Runs `advance(observer)` with an observer that records rows and drift.
/// A row holding a non-finite number is never handed out: the run fails
/// there, naming the column (`columns`), the time and the step.
template <typename System, typename Advance>
SimulationResult observeRun(const Simulation::Model& model, const System& system,
                            const SimulationOptions& options, long n_outputs,
                            const std::vector<std::string>& columns,
                            const std::function<void(const std::vector<double>&)>& row_sink,
                            Advance&& advance, const typename System::State* final_state = nullptr) {
  SimulationResult result;
  DriftTracker drift;
  drift.momentum_conserved = system.conservesAngularMomentum();
  InvariantSet invariants = model.invariants;
  RowBuilder rows{model, options.imu};
  ProgressPacer pacer;
  std::vector<double> row;
  // The last state observed and found good: *final_state where the driver
  // keeps it (integrateFixedStepInPlace), else a copy at every step.
  typename System::State last;
  bool have_last = false;       // none when the run failed at its first state
  double t_last = 0.0;
  bool last_written = false;
  std::string stop_reason;
  double constraint_error = 0.0;
  const auto non_finite = [&](const std::vector<double>& r, long k, double t) {
    const long i = firstNonFinite(r);
    if (i < 0) return false;
    std::ostringstream why;
    why << "the state's " << (static_cast<std::size_t>(i) < columns.size() ? columns[i] : "value")
        << " became non-finite (" << r[i] << ") at t = " << t << " (step " << k
        << "); its magnitude exceeds double precision";
    stop_reason = why.str();
    return true;
  };
  const long check_every = options.check_every > 0 ? options.check_every : options.every;
  result.checked_every = check_every;
  const bool integrates_power = invariants.integratesPower();
  auto observer = [&](long k, double t, const typename System::State& y) {
    last_written = false;
    if (options.progress && pacer.due(k)) options.progress(t, k);
    const bool row_due = k % options.every == 0 || k == n_outputs;
    if (options.diagnostics && integrates_power) invariants.addPower(t, dissipatedPowerOf(system, t, y));
    if (options.diagnostics && (row_due || k % check_every == 0)) {
      drift.observe(system, k, t, y);
      observeInvariants(&invariants, system, y, t);
      constraint_error = std::max(constraint_error, constraintErrorOf(system, t, y));
      if (drift.blownUp()) {
        std::ostringstream why;
        why << "blow-up: the energy error reached " << drift.energy_drift << " times the initial energy at t = "
            << t << " (step " << k << "); the step h = " << options.dt
            << " is beyond this integrator's stability limit";
        stop_reason = why.str();
        return false;
      }
      if (row_sink && row_due) {
        rows(system, t, y, &row);
        if (non_finite(row, k, t)) return false;
        row_sink(row);
        if (options.invariant_sink) options.invariant_sink(t, invariants.current());
        last_written = true;
      }
    }
    if (!final_state) last = y;
    have_last = true;
    t_last = t;
    return true;
  };
  const auto start = std::chrono::steady_clock::now();
  const RunSummary summary = advance(observer);
  const auto stop = std::chrono::steady_clock::now();
  result.wall_seconds = std::chrono::duration<double>(stop - start).count();
  result.steps = summary.steps;
  result.rejected_steps = summary.rejected_steps;
  result.ns_per_step = summary.steps > 0 ? 1e9 * result.wall_seconds / summary.steps : 0.0;
  result.newton_iterations_mean = summary.newtonIterationsMean();
  result.substepped_steps = summary.substepped_steps;
  const typename System::State& good = final_state ? *final_state : last;
  if (have_last) {
    rows(system, t_last, good, &result.final_row);
    if (stop_reason.empty() && !summary.failed) non_finite(result.final_row, summary.steps, t_last);
  }
  result.failed = summary.failed || !stop_reason.empty();
  result.failure = stop_reason.empty() ? summary.failure : stop_reason;
  if (summary.step_limit_reached) result.failure += " (raise the limit with `max_steps`)";
  result.energy_drift = drift.energy_drift;
  result.momentum_conserved = drift.momentum_conserved;
  result.momentum_drift = drift.momentum_drift;
  if (have_last) result.constraint_error = std::max(constraint_error, constraintErrorOf(system, t_last, good));
  if (options.diagnostics)
    for (std::size_t i = 0; i < invariants.names().size(); ++i)
      result.invariants.emplace_back(invariants.names()[i], invariants.maxDrift()[i]);
  // The last good state is always written, whatever `every` is (also when a
  // failure stopped the run between two output steps).
  if (options.diagnostics && row_sink && result.failed && !last_written && have_last &&
      firstNonFinite(result.final_row) < 0)
    row_sink(result.final_row);
  return result;
}

/// Steps `stepper` from y0 over [0, o.t_end] at o.dt through observeRun.
template <typename System, typename Stepper>
SimulationResult runFixedStep(const Simulation::Model& model, const System& system,
                              const typename System::State& y0, const SimulationOptions& o,
                              const std::vector<std::string>& columns,
                              const std::function<void(const std::vector<double>&)>& row, Stepper stepper) {
  typename System::State y = y0;
  return observeRun(
      model, system, o, stepCount(0.0, o.t_end, o.dt), columns, row,
      [&](auto& observer) { return integrateFixedStepInPlace(stepper, system, &y, 0.0, o.t_end, o.dt, observer); },
      &y);
}

}  // namespace simulation_detail
}  // namespace lieflow
