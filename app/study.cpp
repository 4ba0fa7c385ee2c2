#include "app/study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>

#include "app/flag_spelling.hpp"
#include "app/plotting.hpp"
#include "app/run_setup.hpp"
#include "integrators/integrate.hpp"
#include "integrators/registry.hpp"
#include "peers/mujoco/mujoco_peer.hpp"
#include "simulation/invariants.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace app {
namespace {

/// Tolerances of the converged reference run, and of the looser run that
/// estimates its error by tolerance proportionality.
constexpr double kReferenceRtol = 1e-13;
constexpr double kReferenceAtol = 1e-15;
constexpr double kCheckRtol = 1e-11;
constexpr double kCheckAtol = 1e-13;
/// The fixed-step reference's Richardson estimate |y_h − y_2h| / 15 holds
/// where |y_2h − y_4h| is at least this many times |y_h − y_2h| (16 for a
/// fourth-order error in its asymptotic range; between 2³ and 2⁴ to allow
/// for the range's start); else the differences are round-off.
constexpr double kRichardsonMinRatio = 8.0;
/// Drift curves keep about this many samples per integrator.
constexpr int kDriftSamples = 400;

/// The bodies' orientations and angular velocities at the end of a run,
/// the ones the study's errors compare.
struct BodyStates {
  std::vector<Eigen::Quaterniond> q;
  std::vector<Eigen::Vector3d> w;
};

/// Where each body's qw and wx sit in the scene's rows (B.qw, B.wx columns).
struct BodyColumns {
  std::vector<std::size_t> qw, wx;
  explicit BodyColumns(const std::vector<std::string>& columns) {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      const std::string& c = columns[i];
      if (c.size() > 3 && c.compare(c.size() - 3, 3, ".qw") == 0) qw.push_back(i);
      if (c.size() > 3 && c.compare(c.size() - 3, 3, ".wx") == 0) wx.push_back(i);
    }
  }
  BodyStates of(const std::vector<double>& row) const {
    BodyStates s;
    for (std::size_t b = 0; b < qw.size(); ++b) {
      const double* x = row.data() + qw[b];
      s.q.emplace_back(x[0], x[1], x[2], x[3]);
      s.w.emplace_back(row[wx[b]], row[wx[b] + 1], row[wx[b] + 2]);
    }
    return s;
  }
};

/// The largest angle between a body's orientation in `a` and in `ref` [rad]:
/// every body counts (a first body that does not turn hides nothing).
double orientationError(const BodyStates& a, const BodyStates& ref) {
  double e = 0.0;
  for (std::size_t b = 0; b < a.q.size() && b < ref.q.size(); ++b)
    e = std::max(e, (SO3d(a.q[b].normalized()).inverse() * SO3d(ref.q[b].normalized())).log().norm());
  return e;
}

/// Below this largest body rate [rad/s] the reference does not turn: what is
/// left is rounding (a floating robot falling from rest: 1e-17 rad/s, against
/// which an error of 3e-15 rad/s read as 292, relative).
constexpr double kReferenceAtRestRate = 1e-12;

/// The largest ‖ω_b − ω_b,ref‖ over the bodies, relative to the largest
/// ‖ω_b,ref‖; absolute when no body of the reference turns
/// (kReferenceAtRestRate).
double omegaError(const BodyStates& a, const BodyStates& ref) {
  double e = 0.0, scale = 0.0;
  for (std::size_t b = 0; b < a.w.size() && b < ref.w.size(); ++b) {
    e = std::max(e, (a.w[b] - ref.w[b]).norm());
    scale = std::max(scale, ref.w[b].norm());
  }
  return scale > kReferenceAtRestRate ? e / scale : e;
}

/// The heartbeat before a run and as the run's progress callback.
void withHeartbeat(const std::function<void()>& heartbeat, SimulationOptions* o) {
  if (!heartbeat) return;
  heartbeat();
  o->progress = [heartbeat](double, long) { heartbeat(); };
}

/// Output intervals of the replay of a reference that gives no rows of its
/// own (one exact step, or an adaptive run's single output interval).
constexpr int kReplayIntervals = 1000;

std::vector<double> referenceRow(const Simulation& sim, double t_end, const std::string& integrator,
                                 double rtol, double atol, double dt, long max_steps,
                                 const std::function<void()>& heartbeat,
                                 const std::function<void(const std::vector<double>&)>& rows = {}) {
  SimulationOptions o;
  withHeartbeat(heartbeat, &o);
  o.max_steps = max_steps;
  o.integrator = integrator;
  o.dt = dt;
  o.t_end = t_end;
  o.dt_source = "the study's reference step";
  // (Rows are observed only with diagnostics: the replay's run has them.)
  o.diagnostics = static_cast<bool>(rows);
  // Scenes with joints: maximal coordinates, whatever the runs use by
  // default (joint coordinates where they can), so that the reference is
  // computed by other equations than the runs it judges.
  o.formulation = "maximal";
  const IntegratorInfo* info = findIntegrator(integrator);
  const bool adaptive = info && info->is_adaptive;
  if (adaptive) o.integrator_options = {{"rtol", rtol}, {"atol", atol}};
  SimulationResult r;
  try {
    r = sim.run(o, rows);
  } catch (const InvalidInput& e) {
    // Its step is the study's, not one the user gave: say whose it is.
    throw InvalidInput(e.field(), e.reason() + " (in the study's reference run, " + integrator +
                                      (adaptive ? std::string(" at rtol ") + formatNumber(rtol)
                                                              : " at h = " + formatNumber(dt) +
                                                                    ", the smallest studied step / 32 or / 16") +
                                      ")");
  }
  if (r.failed) throw std::runtime_error("the reference run (" + integrator + ") failed: " + r.failure);
  return r.final_row;
}

/// Times a run (`run_once` returns its wall seconds) by repeating it until
/// options.min_timing_seconds were spent (at least min_repeats, at most
/// max_repeats runs) and writes the median, the repeats and ns per step into
/// `row`; a run whose repeats hit the limit first counts in capped_timings.
void timeRow(const StudyOptions& options, const std::function<double()>& run_once, StudyRow* row,
             StudyResult* result) {
  std::vector<double> times;
  double spent = 0.0;
  while (static_cast<int>(times.size()) < options.max_repeats &&
         (static_cast<int>(times.size()) < options.min_repeats || spent < options.min_timing_seconds)) {
    times.push_back(run_once());
    spent += times.back();
  }
  std::sort(times.begin(), times.end());
  if (spent < options.min_timing_seconds) ++result->capped_timings;
  row->repeats = static_cast<int>(times.size());
  row->wall_seconds = times[times.size() / 2];
  row->ns_per_step = row->steps > 0 ? 1e9 * row->wall_seconds / static_cast<double>(row->steps) : 0.0;
}

/// The invariant drifts of a MuJoCo run in the scene's order (NaN, written
/// as an empty cell, for a quantity MuJoCo's run does not measure).
std::vector<double> peerInvariants(const std::vector<std::string>& names, double L, double L_com, double balance) {
  std::vector<double> out;
  for (const std::string& n : names)
    out.push_back(n == "L" ? L : n == "L_com" ? L_com : n == "energy_balance" ? balance
                                                                            : std::numeric_limits<double>::quiet_NaN());
  return out;
}

/// A MuJoCo run's end state, body by body in the scene's order.
BodyStates peerStates(const MujocoPeerRun& run) { return {run.orientations, run.angular_velocities}; }


std::string csvNumber(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

/// MuJoCo's integrators on the model at the study's steps (--with-mujoco):
/// the same measurements as lieflow's rows, from MuJoCo's own quantities,
/// and MuJoCo RK4 at the reference's step as a check of the reference.
void studyMujoco(const MujocoPeer* peer_or_null, double t_end, const std::vector<double>& dts, double drift_dt,
                 const BodyStates& ref, const StudyOptions& options, StudyResult* result) {
  std::string why;
  if (!peer_or_null) {
    mujocoPeerAvailable(&why);
    for (const std::string& name : mujocoPeerIntegrators()) {
      StudyRow row;
      row.integrator = name;
      row.dt = dts.front();
      row.failed = true;
      row.failure = "MuJoCo is absent: " + why;
      result->rows.push_back(row);
    }
    return;
  }
  const MujocoPeer& peer = *peer_or_null;
  // MuJoCo's reference: its RK4 at the smallest step over 32, as lieflow's
  // (where that is a fixed-step run). Each engine's rows are measured against
  // a converged run of its own model, so that an error is the integrator's
  // alone: the two models may differ slightly (MuJoCo balances inertias that
  // break A + B >= C, holds equalities softly), and that difference, said
  // below, is no integrator's error. Its own error is bounded by the
  // difference from RK4 at twice the step (asymptotically, for any order >= 1).
  const double h_check = dts.back() / 32.0;
  if (options.progress) *options.progress << "study: MuJoCo's reference, RK4 at h " << h_check << " and " << 2 * h_check << "\n";
  const MujocoPeerRun check = peer.run("mujoco-rk4", h_check, t_end, false, 1, options.heartbeat);
  const MujocoPeerRun coarse =
      check.failed ? check : peer.run("mujoco-rk4", 2 * h_check, t_end, false, 1, options.heartbeat);
  // How far lieflow's reference lies from MuJoCo's (the models' difference).
  const BodyStates check_states = check.failed ? BodyStates{} : peerStates(check);
  const double references_apart = check.failed ? 0.0 : orientationError(check_states, ref);
  BodyStates peer_ref = ref;
  std::string peer_reference;
  double peer_reference_error = 0.0;
  if (!check.failed && !coarse.failed) {
    peer_ref = check_states;
    peer_reference_error = orientationError(peerStates(coarse), peer_ref);
    peer_reference = "MuJoCo RK4 at h = " + formatNumber(h_check) + " (MuJoCo's own model); its orientation error " +
                     "is below the " + formatNumber(peer_reference_error) + " rad it differs from RK4 at h = " +
                     formatNumber(2 * h_check) + "; lieflow's reference differs from it by " +
                     formatNumber(references_apart) + " rad";
  } else {
    peer_reference = result->reference + " (MuJoCo RK4 at h = " + formatNumber(h_check) +
                     " or twice that failed: " + (check.failed ? check.failure : coarse.failure) + ")";
    peer_reference_error = result->reference_error;
  }
  const std::vector<std::string>& names = result->invariant_names;
  const std::string version = "MuJoCo " + mujocoPeerVersion();
  int done = 0;
  const int total = static_cast<int>(mujocoPeerIntegrators().size() * dts.size());
  for (const std::string& name : mujocoPeerIntegrators()) {
    for (const double dt : dts) {
      if (options.progress)
        *options.progress << "study: [MuJoCo " << ++done << "/" << total << "] " << name << " dt=" << dt << "\n";
      if (options.heartbeat) options.heartbeat();
      StudyRow row;
      row.integrator = name;
      row.dt = dt;
      row.options = version;
      row.reference = peer_reference;
      row.reference_error = peer_reference_error;
      const long steps = stepCount(0.0, t_end, dt);
      if (steps > options.max_steps)
        throw InvalidInput("--max-steps", "MuJoCo's " + std::to_string(steps) + " steps at dt " + formatNumber(dt) +
                                              " exceed the limit " + std::to_string(options.max_steps));
      const MujocoPeerRun diag =
          peer.run(name, dt, t_end, true, std::max(1L, steps / kDriftSamples), options.heartbeat);
      row.steps = diag.steps;
      row.failed = diag.failed;
      row.failure = diag.failure;
      row.momentum_conserved = result->momentum_conserved;
      if (diag.failed) {
        row.orientation_error = row.omega_error = std::numeric_limits<double>::quiet_NaN();
        row.wall_seconds = diag.wall_seconds;
        result->rows.push_back(row);
        continue;
      }
      row.energy_drift = diag.energy_drift;
      row.momentum_drift = diag.momentum_drift;
      row.invariant_drifts = peerInvariants(names, diag.momentum_drift, diag.com_momentum_drift,
                                            diag.energy_balance_drift);
      const BodyStates last = peerStates(diag);
      row.orientation_error = orientationError(last, peer_ref);
      row.omega_error = omegaError(last, peer_ref);
      if (dt == drift_dt) {
        const MujocoPeerSample& s0 = diag.samples.front();
        for (const MujocoPeerSample& s : diag.samples) {
          DriftSample d;
          d.integrator = name;
          d.dt = dt;
          d.t = s.t;
          d.energy_error = relativeDrift(s.energy - s0.energy, s0.energy);
          d.momentum_error = relativeDrift((s.L - s0.L).norm(), s0.L.norm());
          d.invariant_errors = peerInvariants(names, d.momentum_error,
                                              relativeDrift((s.L_com - s0.L_com).norm(), s0.L_com.norm()),
                                              relativeDrift(std::abs(s.energy + s.dissipated_work - s0.energy),
                                                            s0.energy));
          result->drift.push_back(d);
        }
      }
      timeRow(options, [&] { return peer.run(name, dt, t_end, false, 1, options.heartbeat).wall_seconds; }, &row,
              result);
      result->rows.push_back(row);
    }
  }
  // lieflow's reference against MuJoCo's (the models' difference).
  std::ostringstream s;
  if (check.failed)
    s << "; MuJoCo RK4 at h = " << formatNumber(h_check) << " failed: " << check.failure;
  else
    s << "; MuJoCo RK4 at h = " << formatNumber(h_check) << " differs from it by " << formatNumber(references_apart)
      << " rad";
  for (const std::string& note : peer.notes()) s << " (" << note << ")";
  result->reference += s.str();
}

/// The studied steps, longest first: options.dts, or 4, 2, 1, 1/2 and 1/4
/// times the scene's step; none longer than the run.
std::vector<double> studySteps(const Simulation& sim, double t_end, const StudyOptions& options) {
  std::vector<double> dts = options.dts;
  if (dts.empty()) {
    const double dt = sim.scene().has_integrator ? sim.scene().integrator.dt : t_end / 1000.0;
    dts = {4 * dt, 2 * dt, dt, dt / 2, dt / 4};
    if (dts.front() > t_end)
      throw InvalidInput("--t-end", "the study's steps are 4, 2, 1, 1/2 and 1/4 times the scene's step " + formatNumber(dt) +
                                        " s, and the longest, " + formatNumber(dts.front()) +
                                        " s, is longer than the run (t_end = " + formatNumber(t_end) +
                                        " s): give a longer --t-end or the steps (--dt)");
  }
  std::sort(dts.rbegin(), dts.rend());
  if (dts.front() > t_end)
    throw InvalidInput("--dt", "the step " + formatNumber(dts.front()) + " s is longer than the run (t_end = " +
                                   formatNumber(t_end) + " s): give steps no longer than t_end");
  return dts;
}

/// The studied integrators: options.integrators, or every one of the
/// registry that runs this scene (in the formulation asked for). Checked
/// before any run: a scene that none of them can run is refused here, not
/// answered with an empty table after the reference was computed.
std::vector<std::string> studyIntegrators(const Simulation& sim, const StudyOptions& options) {
  std::string why;
  std::vector<std::string> integrators = options.integrators;
  if (integrators.empty()) {
    std::string first_why;
    for (const IntegratorInfo& info : integratorRegistry()) {
      if (info.order == 0) continue;  // an exact flow: the reference, not a studied integrator
      if (sim.supports(info.name, &why, options.formulation))
        integrators.push_back(info.name);
      else if (first_why.empty())
        first_why = why;
    }
    if (integrators.empty())
      throw InvalidInput(options.formulation.empty() ? "scene" : "--formulation",
                         first_why.empty() ? std::string("no integrator can run this scene") : first_why);
  }
  for (const std::string& name : integrators)
    if (!sim.supports(name, &why, options.formulation)) throw InvalidInput("--integrators", why);
  checkOptionKeysUsed(options.integrator_options, integrators);
  return integrators;
}

/// The reference final row the errors are measured against, with what it is
/// and its own estimated error in result->reference, reference_error: the
/// exact flow where there is one, else projected rkmk4 at a step 32 times
/// below the smallest studied one for scenes with joints, else a converged
/// rkmk45 run. Its replay rows go to options.replay_sink.
std::vector<double> studyReference(const Simulation& sim, double t_end, const std::vector<double>& dts,
                                   const BodyColumns& bodies, const StudyOptions& options, StudyResult* result) {
  std::string why;
  std::vector<double> ref;
  const bool exact_reference = sim.supports("exact", &why);
  if (exact_reference) {
    ref = referenceRow(sim, t_end, "exact", 0, 0, t_end, options.max_steps, options.heartbeat);
    if (options.replay_sink)
      referenceRow(sim, t_end, "exact", 0, 0, t_end / kReplayIntervals, options.max_steps, options.heartbeat,
                   options.replay_sink);
    result->reference = "exact flow (Jacobi elliptic functions)";
    result->reference_error = 0.0;
  } else if (sim.hasConstraints()) {
    // Scenes with joints: the projected rkmk4 in maximal coordinates
    // (referenceRow) at a step 32 times below the smallest studied one.
    // (Fixed steps: independent of the adaptive driver's projection, which
    // rkmk45 runs with here, and of any integrator the study compares.) Its
    // error: Richardson's |y_h − y_2h| / 15 where the runs at 2h and 4h show
    // that halving the step divides the difference by about 16 (h⁴ rules
    // it); where they do not, the differences are round-off — which a
    // chaotic motion amplifies: on the Panda's fall they stay near 4e-10 rad
    // from 1e-6 s down — and |y_h − y_2h| itself bounds the error (as it
    // bounds MuJoCo's reference's below), not a fifteenth of it.
    const double h_ref = dts.back() / 32.0;
    if (options.progress) *options.progress << "study: computing the reference (projected rkmk4, h " << h_ref << ")\n";
    ref = referenceRow(sim, t_end, "rkmk4", 0, 0, h_ref, options.max_steps, options.heartbeat, options.replay_sink);
    const std::vector<double> check =
        referenceRow(sim, t_end, "rkmk4", 0, 0, 2 * h_ref, options.max_steps, options.heartbeat);
    const std::vector<double> coarse =
        referenceRow(sim, t_end, "rkmk4", 0, 0, 4 * h_ref, options.max_steps, options.heartbeat);
    const double fine_apart = orientationError(bodies.of(ref), bodies.of(check));
    const double coarse_apart = orientationError(bodies.of(check), bodies.of(coarse));
    const bool fourth_order = coarse_apart >= kRichardsonMinRatio * fine_apart;
    result->reference_error = fourth_order ? fine_apart / 15.0 : fine_apart;
    std::ostringstream s;
    s << "projected rkmk4 at h = " << formatNumber(h_ref) << "; its orientation error is estimated at "
      << formatNumber(result->reference_error) << " rad ";
    const std::string times = fine_apart > 0.0 ? formatNumber(coarse_apart / fine_apart) : "infinitely many";
    if (fourth_order)
      s << "by Richardson from a run at h = " << formatNumber(2 * h_ref) << " (the run at " << formatNumber(4 * h_ref)
        << " differs " << times << " times more: fourth order)";
    else
      s << "as its difference from a run at h = " << formatNumber(2 * h_ref) << " (round-off: the run at "
        << formatNumber(4 * h_ref) << " differs only " << times << " times more, not the 16 of fourth order)";
    result->reference = s.str();
  } else {
    if (options.progress) *options.progress << "study: computing the reference (rkmk45, rtol 1e-13)\n";
    ref = referenceRow(sim, t_end, "rkmk45", kReferenceRtol, kReferenceAtol, t_end, options.max_steps,
                       options.heartbeat);
    if (options.replay_sink)
      referenceRow(sim, t_end, "rkmk45", kReferenceRtol, kReferenceAtol, t_end / kReplayIntervals, options.max_steps,
                   options.heartbeat, options.replay_sink);
    const std::vector<double> check =
        referenceRow(sim, t_end, "rkmk45", kCheckRtol, kCheckAtol, t_end, options.max_steps, options.heartbeat);
    result->reference_error = orientationError(bodies.of(ref), bodies.of(check)) * (kReferenceRtol / kCheckRtol);
    std::ostringstream s;
    s << "converged rkmk45 run (Dormand-Prince 5(4) on the group, rtol " << kReferenceRtol
      << ", atol " << kReferenceAtol << "); its orientation error is estimated at "
      << formatNumber(result->reference_error) << " rad from a run at rtol " << kCheckRtol;
    result->reference = s.str();
  }
  return ref;
}

/// Where a run's row holds the energy and the spatial angular momentum, and
/// the step whose drift curves the study draws.
struct DriftColumns {
  std::size_t energy = 0, lx = 0;
  double dt = 0.0;
};

/// One case of the study: `name` at step dt, its diagnostics run (drift
/// figures, failure, Newton iterations; drift curves at drift.dt) and its
/// timing runs, appended to result->rows.
void studyCase(const Simulation& sim, const std::string& name, double dt, double t_end, const StudyOptions& options,
               const DriftColumns& drift, const BodyColumns& bodies, const std::vector<double>& ref,
               StudyResult* result) {
  SimulationOptions o;
  o.integrator = name;
  o.formulation = options.formulation;
  o.dt = dt;
  o.t_end = t_end;
  if (options.dts.empty()) o.dt_source = "the study's steps (4, 2, 1, 1/2, 1/4 times the scene's)";
  o.max_steps = options.max_steps;
  withHeartbeat(options.heartbeat, &o);
  applyIntegratorOptions(sim.scene(), options.integrator_options, &o);

  // Diagnostics run: drift figures, failure, Newton iterations; drift
  // curves for the chosen step.
  StudyRow row;
  row.integrator = name;
  row.dt = dt;
  row.options = describeOptions(o);
  const long steps = stepCount(0.0, t_end, dt);
  const bool record_drift = dt == drift.dt;
  o.every = static_cast<int>(std::max(1L, steps / kDriftSamples));
  o.check_every = 1;  // the drift figures are this run's result: every step
  std::vector<double> first;
  if (record_drift)
    o.invariant_sink = [&](double, const std::vector<double>& errors) {
      result->drift.back().invariant_errors = errors;
    };
  const SimulationResult diag = sim.run(o, [&](const std::vector<double>& r) {
    if (!record_drift) return;
    if (first.empty()) first = r;
    DriftSample s;
    s.integrator = name;
    s.dt = dt;
    s.t = r[0];
    const double e0 = first[drift.energy];
    s.energy_error = relativeDrift(r[drift.energy] - e0, e0);
    const Eigen::Vector3d L0(first[drift.lx], first[drift.lx + 1], first[drift.lx + 2]);
    const Eigen::Vector3d L(r[drift.lx], r[drift.lx + 1], r[drift.lx + 2]);
    s.momentum_error = relativeDrift((L - L0).norm(), L0.norm());
    result->drift.push_back(s);
  });
  row.steps = diag.steps;
  row.energy_drift = diag.energy_drift;
  row.momentum_conserved = diag.momentum_conserved;
  row.momentum_drift = diag.momentum_drift;
  for (const auto& inv : diag.invariants) row.invariant_drifts.push_back(inv.second);
  row.implicit = diag.implicit;
  row.newton_iterations_mean = diag.newton_iterations_mean;
  row.failed = diag.failed;
  row.failure = diag.failure;
  result->momentum_conserved = diag.momentum_conserved;
  if (diag.failed) {
    row.orientation_error = row.omega_error = std::numeric_limits<double>::quiet_NaN();
    row.wall_seconds = diag.wall_seconds;
    result->rows.push_back(row);
    return;
  }
  row.orientation_error = orientationError(bodies.of(diag.final_row), bodies.of(ref));
  row.omega_error = omegaError(bodies.of(diag.final_row), bodies.of(ref));

  // Timing runs: diagnostics off, repeated; the median is reported.
  o.diagnostics = false;
  o.invariant_sink = nullptr;
  timeRow(options, [&] { return sim.run(o).wall_seconds; }, &row, result);
  result->rows.push_back(row);
}

}  // namespace

StudyResult runStudy(const Simulation& sim, double t_end, const StudyOptions& options) {
  StudyResult result;
  result.scene = sim.scene().name;
  result.t_end = t_end;
  const std::vector<double> dts = studySteps(sim, t_end, options);
  const std::vector<std::string> integrators = studyIntegrators(sim, options);
  // MuJoCo beside lieflow: its model is compiled and matched to the scene
  // now, so that a model MuJoCo cannot run is refused before lieflow's runs.
  std::unique_ptr<MujocoPeer> peer;
  if (!options.mujoco_model.empty() && mujocoPeerAvailable(nullptr))
    peer = std::make_unique<MujocoPeer>(options.mujoco_model, options.mujoco_import, sim.scene());
  const BodyColumns bodies(sim.columns());
  const std::vector<double> ref = studyReference(sim, t_end, dts, bodies, options, &result);
  result.invariant_names = sim.invariantNames();

  const std::vector<std::string> columns = sim.columns();
  const auto column = [&](const std::string& c) {
    return static_cast<std::size_t>(std::find(columns.begin(), columns.end(), c) - columns.begin());
  };
  DriftColumns drift;
  drift.energy = column("energy");
  drift.lx = column("Lx");
  drift.dt = std::find(dts.begin(), dts.end(), sim.scene().integrator.dt) != dts.end() ? sim.scene().integrator.dt
                                                                                      : dts[dts.size() / 2];
  int done = 0;
  const int total = static_cast<int>(integrators.size() * dts.size());
  for (const std::string& name : integrators) {
    for (const double dt : dts) {
      ++done;
      if (options.progress)
        *options.progress << "study: [" << done << "/" << total << "] " << name << " dt=" << dt << "\n";
      studyCase(sim, name, dt, t_end, options, drift, bodies, ref, &result);
    }
  }
  if (!options.mujoco_model.empty()) studyMujoco(peer.get(), t_end, dts, drift.dt, bodies.of(ref), options, &result);
  return result;
}

void writeStudyFiles(const StudyResult& result, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const std::string study_path = dir + "/study.csv";
  std::ofstream study(study_path);
  if (!study) throw InvalidInput(study_path, "cannot open for writing");
  study << "scene,integrator,dt,steps,repeats,wall_seconds,ns_per_step,orientation_error,omega_error,"
           "energy_drift,momentum_drift,newton_iterations_mean,failed,failure,reference,reference_error,options";
  for (const std::string& name : result.invariant_names) study << "," << name << "_drift";
  study << "\n";
  // A failed row has no error, time or drift: empty cells, never NaN.
  const auto cell = [](bool valid, double v) { return valid && std::isfinite(v) ? csvNumber(v) : std::string(); };
  for (const StudyRow& r : result.rows) {
    std::string failure = spellFlags(r.failure);
    std::replace(failure.begin(), failure.end(), '"', '\'');
    const bool ok = !r.failed;
    study << result.scene << "," << r.integrator << "," << csvNumber(r.dt) << "," << r.steps << ","
          << r.repeats << "," << cell(ok, r.wall_seconds) << "," << cell(ok, r.ns_per_step) << ","
          << cell(ok, r.orientation_error) << "," << cell(ok, r.omega_error) << ","
          << cell(ok, r.energy_drift) << "," << cell(ok && r.momentum_conserved, r.momentum_drift) << ","
          << cell(r.implicit, r.newton_iterations_mean) << "," << (r.failed ? "true" : "false") << ",\"" << failure
          << "\",\"" << spellFlags(r.reference.empty() ? result.reference : r.reference) << "\","
          << csvNumber(r.reference.empty() ? result.reference_error : r.reference_error) << ",\"" << r.options << "\"";
    for (std::size_t i = 0; i < result.invariant_names.size(); ++i)
      study << "," << cell(ok && i < r.invariant_drifts.size(), i < r.invariant_drifts.size() ? r.invariant_drifts[i] : 0.0);
    study << "\n";
  }
  const std::string drift_path = dir + "/drift.csv";
  std::ofstream drift(drift_path);
  if (!drift) throw InvalidInput(drift_path, "cannot open for writing");
  drift << "integrator,dt,t,energy_error,momentum_error";
  for (const std::string& name : result.invariant_names) drift << "," << name << "_error";
  drift << "\n";
  for (const DriftSample& s : result.drift) {
    drift << s.integrator << "," << csvNumber(s.dt) << "," << csvNumber(s.t) << "," << csvNumber(s.energy_error) << ","
          << (result.momentum_conserved ? csvNumber(s.momentum_error) : "");
    for (std::size_t i = 0; i < result.invariant_names.size(); ++i)
      drift << "," << (i < s.invariant_errors.size() ? csvNumber(s.invariant_errors[i]) : "");
    drift << "\n";
  }
}

bool plotStudy(const std::string& dir, std::string* why) {
  return runPlotScript("plot_study.py", dir, why);
}

void printStudyTable(std::ostream& out, const StudyResult& result) {
  out << "scene " << result.scene << ", t_end = " << result.t_end << " s; errors at t_end against the "
      << spellFlags(result.reference) << "\n\n";
  out << "| integrator | dt | steps | time [ms] | ns/step | orientation error [rad] | omega error (rel; rad/s when the reference is at rest) | "
         "energy drift | momentum drift | Newton its |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const StudyRow& r : result.rows) {
    out << "| " << r.integrator << " | " << formatNumber(r.dt) << " | " << r.steps << " | ";
    if (r.failed) {
      out << "failed | failed | failed: " << spellFlags(r.failure) << " | | | | |\n";
      continue;
    }
    out << formatNumber(1e3 * r.wall_seconds) << " | " << formatNumber(r.ns_per_step) << " | ";
    out << formatNumber(r.orientation_error) << " | " << formatNumber(r.omega_error) << " | "
        << formatNumber(r.energy_drift) << " | " << (r.momentum_conserved ? formatNumber(r.momentum_drift) : "n/a")
        << " | " << (r.implicit ? formatNumber(r.newton_iterations_mean) : "-") << " |\n";
  }
  // Rows measured against another reference (MuJoCo's rows: its own), once.
  std::vector<std::string> said;
  for (const StudyRow& r : result.rows)
    if (!r.reference.empty() && std::find(said.begin(), said.end(), r.reference) == said.end()) {
      said.push_back(r.reference);
      out << "\nMuJoCo's rows: errors against the " << spellFlags(r.reference)
          << "\n";
    }
}

}  // namespace app
}  // namespace lieflow
