/// \file
/// bench_work_precision OUTDIR [--repeats N] [--t-end T] [--max-steps N]
///
/// Work-precision study on the benchmark free body (free_body_scene.hpp) over
/// T = 10 s: for lieflow's rkmk4, cf4, lgvi, splitting, genalpha and, when this
/// binary has MuJoCo, MuJoCo's Euler and RK4 (mj_step, mujoco_peer.hpp), at
/// N = 100·2^k steps (h = T/N), the run time of the N steps (median of the
/// repeats, at least 3, more for runs under 50 ms) and the errors at T against
/// lieflow's exact Euler–Poinsot flow (ExactFreeRigidBody, ~1e-13): the
/// orientation error angle(R_exact⁻¹ R), ‖ω − ω_exact‖ (body frame) and the
/// position error (exact p0 + v0 T).
///
/// Writes OUTDIR/work_precision.csv and OUTDIR/work_precision_summary.md, and
/// prints the summary: for MuJoCo RK4's runs with orientation error < 1e-6,
/// the accuracy ratio at equal run time, err_MuJoCo(t) / err_lieflow(t), where
/// err_lieflow(t) is the best error the lieflow method reached within run
/// time t (log-log interpolation between its runs, the lower envelope in t:
/// never an extrapolation beyond its measured runs), for rkmk4 and cf4; the
/// target is ≥ 100 for lieflow's best fourth-order method. Plot with
/// bench/integrators/plot_work_precision.py OUTDIR/work_precision.csv.
///
/// The exit status is 0 whatever the ratios; 2 for bad arguments, 1 if OUTDIR
/// cannot be written.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench/integrators/free_body_scene.hpp"
#include "bench/integrators/mujoco_peer.hpp"
#include "integrators/butcher_tableau.hpp"
#include "integrators/commutator_free.hpp"
#include "integrators/generalized_alpha.hpp"
#include "integrators/lgvi.hpp"
#include "integrators/rkmk.hpp"
#include "integrators/splitting.hpp"

namespace {

using lieflow::bench::FreeBodyScene;
using lieflow::bench::MujocoFreeBody;
using Clock = std::chrono::steady_clock;

/// Errors below this are where the accuracy target applies.
constexpr double kErrorThreshold = 1e-6;
/// Target: MuJoCo RK4 error / lieflow's best 4th-order error ≥ 100 at equal time.
constexpr double kAccuracyRatioTarget = 100.0;
/// Runs shorter than this are repeated until the repeats add up to it.
constexpr double kMinTotalSeconds = 0.05;
constexpr int kMaxRepeats = 101;

struct Options {
  std::string out_dir;
  int repeats = 3;
  double t_end = 10.0;
  long max_steps = 819200;
};

struct Point {
  std::string method;
  std::string family;  // lieflow | mujoco
  int order = 0;
  long steps = 0;
  double h = 0.0;
  double seconds = 0.0;  // median over the repeats
  int repeats = 0;
  double orientation_error = 0.0;
  double omega_error = 0.0;
  double position_error = 0.0;
  bool failed = false;
};

struct Errors {
  Eigen::Quaterniond q;
  Eigen::Vector3d omega, p;
  bool failed = false;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Times `run` (which returns the final state): once, then enough further
/// repeats for at least opts.repeats in all and kMinTotalSeconds together.
Errors timeRuns(const Options& opts, const std::function<Errors()>& run, double* seconds,
                int* repeats) {
  std::vector<double> times;
  Errors final_state;
  double total = 0.0;
  while (static_cast<int>(times.size()) < opts.repeats ||
         (total < kMinTotalSeconds && static_cast<int>(times.size()) < kMaxRepeats)) {
    const auto start = Clock::now();
    final_state = run();
    const double s = std::chrono::duration<double>(Clock::now() - start).count();
    times.push_back(s);
    total += s;
  }
  if (times.size() % 2 == 0) {  // an odd count: the median is a measured run
    const auto start = Clock::now();
    final_state = run();
    times.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  *seconds = median(times);
  *repeats = static_cast<int>(times.size());
  return final_state;
}

/// N steps of a lieflow stepper on the free body, from the scene's initial state.
template <typename Stepper>
std::function<Errors()> lieflowRun(const FreeBodyScene& scene,
                                   const lieflow::FreeBodySystem<double>& system, Stepper stepper,
                                   long n, double t_end) {
  return [&scene, &system, stepper, n, t_end]() mutable {
    lieflow::FreeBodyState<double> y = scene.freeBodyState();
    const double h = t_end / static_cast<double>(n);
    bool failed = false;
    lieflow::StepReport report;
    for (long k = 0; k < n; ++k) {
      y = stepper.step(system, static_cast<double>(k) * h, y, h, &report);
      failed = failed || !report.converged;
    }
    Errors e;
    e.q = y.R.quaternion();
    e.omega = y.omega;
    e.p = y.p;
    e.failed = failed || !lieflow::isFinite(y);
    return e;
  };
}

template <typename Stepper>
void measureLieflow(const Options& opts, const FreeBodyScene& scene, const std::string& name,
                    int order, const Stepper& stepper, const Errors& exact,
                    std::vector<Point>* points) {
  for (long n = 100; n <= opts.max_steps; n *= 2) {
    Point p;
    p.method = name;
    p.family = "lieflow";
    p.order = order;
    p.steps = n;
    p.h = opts.t_end / static_cast<double>(n);
    const lieflow::FreeBodySystem<double> system = scene.freeBodySystem();
    const Errors e =
        timeRuns(opts, lieflowRun(scene, system, stepper, n, opts.t_end), &p.seconds, &p.repeats);
    p.orientation_error = lieflow::bench::orientationError(exact.q, e.q);
    p.omega_error = (e.omega - exact.omega).norm();
    p.position_error = (e.p - exact.p).norm();
    p.failed = e.failed;
    points->push_back(p);
    std::fprintf(stderr, "  %-16s N = %7ld  %10.3e s  orientation error %.3e%s\n", name.c_str(), n,
                 p.seconds, p.orientation_error, p.failed ? "  (FAILED)" : "");
  }
}

void measureMujoco(const Options& opts, const FreeBodyScene& scene, const std::string& name,
                   MujocoFreeBody::Integrator integrator, const Errors& exact,
                   std::vector<Point>* points) {
  for (long n = 100; n <= opts.max_steps; n *= 2) {
    const double h = opts.t_end / static_cast<double>(n);
    auto body = std::make_shared<MujocoFreeBody>(scene, integrator, h);
    Point p;
    p.method = name;
    p.family = "mujoco";
    p.order = integrator == MujocoFreeBody::Integrator::kRk4 ? 4 : 1;
    p.steps = n;
    p.h = h;
    const Errors e = timeRuns(
        opts,
        [body, n]() {
          body->reset();
          body->steps(n);
          Errors r;
          r.q = body->orientation();
          r.omega = body->angularVelocityBody();
          r.p = body->position();
          r.failed = !std::isfinite(r.q.coeffs().sum() + r.omega.sum() + r.p.sum());
          return r;
        },
        &p.seconds, &p.repeats);
    if (std::abs(body->time() - opts.t_end) > 1e-9 * opts.t_end)
      std::fprintf(stderr, "  warning: MuJoCo time %.17g after %ld steps (T = %g)\n", body->time(),
                   n, opts.t_end);
    p.orientation_error = lieflow::bench::orientationError(exact.q, e.q);
    p.omega_error = (e.omega - exact.omega).norm();
    p.position_error = (e.p - exact.p).norm();
    p.failed = e.failed;
    points->push_back(p);
    std::fprintf(stderr, "  %-16s N = %7ld  %10.3e s  orientation error %.3e%s\n", name.c_str(), n,
                 p.seconds, p.orientation_error, p.failed ? "  (FAILED)" : "");
  }
}

/// The best orientation error a method reached within run time t: log-log
/// interpolation between its runs sorted by time, then the running minimum
/// (more time never has to give a worse error: the cheaper run is available).
/// +inf below its fastest run; its overall best beyond its slowest run.
double bestErrorWithin(const std::vector<Point>& pts, double t, bool* beyond) {
  std::vector<Point> s;
  for (const Point& p : pts)
    if (!p.failed && p.orientation_error > 0.0) s.push_back(p);
  std::sort(s.begin(), s.end(),
            [](const Point& a, const Point& b) { return a.seconds < b.seconds; });
  *beyond = false;
  if (s.empty() || t < s.front().seconds) return std::numeric_limits<double>::infinity();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i].seconds <= t) best = std::min(best, s[i].orientation_error);
    if (i + 1 < s.size() && s[i].seconds <= t && t < s[i + 1].seconds) {
      const double x = (std::log(t) - std::log(s[i].seconds)) /
                       (std::log(s[i + 1].seconds) - std::log(s[i].seconds));
      const double e = std::exp((1.0 - x) * std::log(s[i].orientation_error) +
                                x * std::log(s[i + 1].orientation_error));
      return std::min(best, e);
    }
  }
  *beyond = t > s.back().seconds;
  return best;
}

/// The least run time in which a method reaches orientation error e
/// (log-log interpolation along its runs sorted by time); +inf if never.
double timeToReach(const std::vector<Point>& pts, double e) {
  std::vector<Point> s;
  for (const Point& p : pts)
    if (!p.failed && p.orientation_error > 0.0) s.push_back(p);
  std::sort(s.begin(), s.end(),
            [](const Point& a, const Point& b) { return a.seconds < b.seconds; });
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i].orientation_error <= e) {
      if (i == 0) return s[0].seconds;
      const double a = std::log(s[i - 1].orientation_error), b = std::log(s[i].orientation_error);
      const double x = (std::log(e) - a) / (b - a);
      return std::exp((1.0 - x) * std::log(s[i - 1].seconds) + x * std::log(s[i].seconds));
    }
  }
  return std::numeric_limits<double>::infinity();
}

std::vector<Point> select(const std::vector<Point>& all, const std::string& method) {
  std::vector<Point> r;
  for (const Point& p : all)
    if (p.method == method) r.push_back(p);
  return r;
}

std::string sci(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2e", x);
  return buf;
}
std::string fix(double x, int d) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", d, x);
  return buf;
}

/// The accuracy-ratio summary (markdown).
std::string summarize(const Options& opts, const FreeBodyScene& scene,
                      const std::vector<Point>& all) {
  std::ostringstream out;
  out << "## Work-precision summary (T = " << opts.t_end << " s)\n\n"
      << scene.describe() << ".\n\n";
  const std::vector<Point> mj = select(all, "mujoco-rk4");
  if (mj.empty()) {
    out << "MuJoCo RK4 not measured (" << lieflow::bench::mujocoDescription()
        << "): no accuracy ratio at equal run time.\n";
    return out.str();
  }
  const char* const candidates[] = {"rkmk4", "cf4"};
  double best_min_ratio = -1.0;
  std::string best_method;
  for (const char* method : candidates) {
    const std::vector<Point> lf = select(all, method);
    out << "### MuJoCo RK4 vs lieflow " << method << "\n\n"
        << "| N (MuJoCo) | run time (s) | MuJoCo RK4 error | lieflow " << method
        << " best error within that time | accuracy ratio | lieflow time to MuJoCo's error (s)"
           " | speed ratio at equal error |\n"
        << "| ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    double min_ratio = std::numeric_limits<double>::infinity();
    int rows = 0;
    for (const Point& m : mj) {
      if (m.failed || !(m.orientation_error < kErrorThreshold)) continue;
      bool beyond = false;
      const double e = bestErrorWithin(lf, m.seconds, &beyond);
      const double ratio = m.orientation_error / e;
      const double t_lf = timeToReach(lf, m.orientation_error);
      min_ratio = std::min(min_ratio, ratio);
      ++rows;
      out << "| " << m.steps << " | " << sci(m.seconds) << " | " << sci(m.orientation_error)
          << " | " << sci(e) << (beyond ? " (all its runs)" : "") << " | " << sci(ratio) << " | "
          << (std::isfinite(t_lf) ? sci(t_lf) : "-") << " | "
          << (std::isfinite(t_lf) ? fix(m.seconds / t_lf, 1) : "-") << " |\n";
    }
    if (rows == 0) {
      out << "\nMuJoCo RK4 did not reach an orientation error below " << sci(kErrorThreshold)
          << " within " << opts.max_steps << " steps.\n\n";
      continue;
    }
    out << "\nMinimum accuracy ratio over MuJoCo RK4's runs below " << sci(kErrorThreshold) << ": "
        << sci(min_ratio) << " (target >= " << kAccuracyRatioTarget << ": "
        << (min_ratio >= kAccuracyRatioTarget ? "PASS" : "MISS") << ").\n\n";
    if (min_ratio > best_min_ratio) {
      best_min_ratio = min_ratio;
      best_method = method;
    }
  }
  if (best_min_ratio > 0) {
    out << "**Best lieflow 4th-order method: " << best_method
        << ", accuracy ratio at equal run time >= " << sci(best_min_ratio)
        << " for MuJoCo RK4 errors below " << sci(kErrorThreshold)
        << " (target >= " << kAccuracyRatioTarget << ": "
        << (best_min_ratio >= kAccuracyRatioTarget ? "PASS" : "MISS") << ").**\n\n";
  }
  out << "Accuracy ratio = MuJoCo RK4 orientation error / the best orientation error lieflow "
         "reached within the same run time (log-log interpolation between its runs; \"(all its "
         "runs)\": MuJoCo's time exceeds lieflow's slowest run, whose error is used, so lieflow "
         "used less time). Run time: median of the repeats of the whole N-step loop. Exact "
         "reference: ExactFreeRigidBody (~1e-13).\n";
  return out.str();
}

int usage(const char* argv0) {
  std::cerr << "usage: " << argv0
            << " OUTDIR [--repeats N (>= 1, default 3)] [--t-end T (default 10)]"
               " [--max-steps N (default 819200)]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  Options opts;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* flag) -> const char* {
      if (i + 1 >= argc) {
        std::cerr << "bench_work_precision: " << flag << " needs a value\n";
        std::exit(usage(argv[0]));
      }
      return argv[++i];
    };
    if (a == "--repeats") {
      opts.repeats = std::atoi(value("--repeats"));
    } else if (a == "--t-end") {
      opts.t_end = std::atof(value("--t-end"));
    } else if (a == "--max-steps") {
      opts.max_steps = std::atol(value("--max-steps"));
    } else if (a == "-h" || a == "--help") {
      return usage(argv[0]), 0;
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << "bench_work_precision: unknown option '" << a << "'\n";
      return usage(argv[0]);
    } else if (opts.out_dir.empty()) {
      opts.out_dir = a;
    } else {
      std::cerr << "bench_work_precision: more than one OUTDIR ('" << opts.out_dir << "', '" << a
                << "')\n";
      return usage(argv[0]);
    }
  }
  if (opts.out_dir.empty()) {
    std::cerr << "bench_work_precision: OUTDIR is required\n";
    return usage(argv[0]);
  }
  if (opts.repeats < 1 || !(opts.t_end > 0.0) || opts.max_steps < 100) {
    std::cerr << "bench_work_precision: --repeats must be >= 1, --t-end > 0, --max-steps >= 100\n";
    return usage(argv[0]);
  }
  const std::string csv_path = opts.out_dir + "/work_precision.csv";
  const std::string summary_path = opts.out_dir + "/work_precision_summary.md";
  std::ofstream csv(csv_path);
  if (!csv) {
    std::cerr << "bench_work_precision: cannot write " << csv_path
              << " (does the directory exist?)\n";
    return 1;
  }

  const FreeBodyScene scene;
  Errors exact;
  scene.exact().evaluate(opts.t_end, &exact.q, &exact.omega);
  exact.p = scene.p0 + opts.t_end * scene.v0_world;
  std::cerr << "bench_work_precision: " << scene.describe() << "; T = " << opts.t_end << " s; "
            << lieflow::bench::mujocoDescription() << "\n";

  using State = lieflow::FreeBodyState<double>;
  std::vector<Point> points;
  measureLieflow(opts, scene, "rkmk4", 4,
                 lieflow::RkmkStepper<State>(lieflow::ButcherTableau::rk4()), exact, &points);
  measureLieflow(opts, scene, "cf4", 4, lieflow::CommutatorFree4Stepper<State>(), exact, &points);
  measureLieflow(opts, scene, "lgvi", 2, lieflow::LgviStepper<State>(), exact, &points);
  measureLieflow(opts, scene, "splitting", 2, lieflow::SplittingStepper<State>(scene.inertia()),
                 exact, &points);
  measureLieflow(opts, scene, "genalpha", 2, lieflow::GeneralizedAlphaStepper<State>(), exact,
                 &points);
  if (lieflow::bench::mujocoAvailable()) {
    measureMujoco(opts, scene, "mujoco-euler", MujocoFreeBody::Integrator::kEuler, exact, &points);
    measureMujoco(opts, scene, "mujoco-rk4", MujocoFreeBody::Integrator::kRk4, exact, &points);
  }

  csv << "method,family,order,steps,h,seconds,repeats,ns_per_step,orientation_error,omega_error,"
         "position_error,failed\n";
  csv.precision(6);
  for (const Point& p : points) {
    char line[512];
    std::snprintf(line, sizeof line, "%s,%s,%d,%ld,%.17g,%.6e,%d,%.2f,%.6e,%.6e,%.6e,%d\n",
                  p.method.c_str(), p.family.c_str(), p.order, p.steps, p.h, p.seconds, p.repeats,
                  1e9 * p.seconds / static_cast<double>(p.steps), p.orientation_error,
                  p.omega_error, p.position_error, p.failed ? 1 : 0);
    csv << line;
  }
  csv.close();

  const std::string summary = summarize(opts, scene, points);
  std::ofstream(summary_path) << summary;
  std::cout << summary << "\nwrote " << csv_path << " and " << summary_path << "\n";
  return 0;
}
