#include "calibration/hinge_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "calibration/hinge_residuals.hpp"
#include "calibration/unit_axis.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// Iterations of a start on the subsample, and of a polish on all samples.
constexpr int kStartIterations = 40;
constexpr int kPolishIterations = 60;
/// A descent ends when the Gauss–Newton model promises less than this
/// fraction of the cost (or a step gains less): starts on the subsample, and
/// polishes on all samples.
constexpr double kStartTolerance = 1e-4;
constexpr double kPolishTolerance = 1e-12;
/// A start is abandoned where its cost stays above kAbandonFactor times the
/// best minimum's so far while falling by less than kCrawl per step.
constexpr double kAbandonFactor = 10.0;
constexpr double kCrawl = 0.01;
/// Coarse minima within this Δχ² of the best (on the subsample, against the
/// best's residual variance there) are polished on all samples.
constexpr double kPolishChiSquare = 50.0;
/// A start that comes this close to a minimum found before ends there (deg).
constexpr double kJoinDeg = 2.0;

/// One sample, as the residual needs it.
struct RateSample {
  Eigen::Vector3d w1, w2;
  double n1, n2;   ///< ‖ω₁‖², ‖ω₂‖²
  double floor_sq; ///< as GyroHingeResidual::floor_sq
};

using Vector4 = Eigen::Matrix<double, 4, 1>;
using Matrix4 = Eigen::Matrix<double, 4, 4>;

/// Tangent basis (u, v) of a unit axis j: j ← normalize(j + δ₀u + δ₁v) turns it by |δ| rad (to first order).
struct Frame {
  Eigen::Vector3d j, u, v;
  explicit Frame(const Eigen::Vector3d& axis) : j(axis.normalized()), u(orthogonalUnit(j)), v(j.cross(u)) {}
  Eigen::Vector3d moved(double d0, double d1) const { return (j + d0 * u + d1 * v).normalized(); }
};

/// Σ r² over samples[0], samples[stride], ...; with H and g non-null also the
/// Gauss–Newton normal equations JᵀJ and Jᵀr in the frames' tangent coordinates.
double evaluate(const std::vector<RateSample>& samples, std::size_t stride, const Frame& f1, const Frame& f2,
                Matrix4* H, Vector4* g) {
  double cost = 0.0;
  if (!H) {
    for (std::size_t k = 0; k < samples.size(); k += stride) {
      const RateSample& s = samples[k];
      const double a1 = s.w1.dot(f1.j), a2 = s.w2.dot(f2.j);
      const double p1 = s.n1 - a1 * a1, p2 = s.n2 - a2 * a2;
      const double d = p1 - p2;
      cost += d * d / (4.0 * (p1 + p2 + s.floor_sq));
    }
    return cost;
  }
  // The 10 entries of the symmetric JᵀJ and the 4 of Jᵀr, accumulated as scalars.
  double h00 = 0, h01 = 0, h02 = 0, h03 = 0, h11 = 0, h12 = 0, h13 = 0, h22 = 0, h23 = 0, h33 = 0;
  double g0 = 0, g1 = 0, g2 = 0, g3 = 0;
  for (std::size_t k = 0; k < samples.size(); k += stride) {
    const RateSample& s = samples[k];
    const double a1 = s.w1.dot(f1.j), a2 = s.w2.dot(f2.j);
    const double p1 = s.n1 - a1 * a1, p2 = s.n2 - a2 * a2;
    const double sum = p1 + p2 + s.floor_sq;
    const double inverse_root = 1.0 / std::sqrt(sum);
    const double r = 0.5 * (p1 - p2) * inverse_root;
    cost += r * r;
    // ∂p₁/∂δ = −2 (ω₁·j₁)(ω₁·u₁, ω₁·v₁); ∂r = (∂p₁ − ∂p₂)/D − r (∂p₁ + ∂p₂)/(2 sum), D = 2√sum.
    const double c = r / (2.0 * sum), e = 0.5 * inverse_root;
    const double m1 = -2.0 * a1 * (e - c), m2 = 2.0 * a2 * (e + c);
    const double J0 = m1 * s.w1.dot(f1.u), J1 = m1 * s.w1.dot(f1.v);
    const double J2 = m2 * s.w2.dot(f2.u), J3 = m2 * s.w2.dot(f2.v);
    h00 += J0 * J0; h01 += J0 * J1; h02 += J0 * J2; h03 += J0 * J3;
    h11 += J1 * J1; h12 += J1 * J2; h13 += J1 * J3;
    h22 += J2 * J2; h23 += J2 * J3; h33 += J3 * J3;
    g0 += r * J0; g1 += r * J1; g2 += r * J2; g3 += r * J3;
  }
  *H << h00, h01, h02, h03, h01, h11, h12, h13, h02, h12, h22, h23, h03, h13, h23, h33;
  *g << g0, g1, g2, g3;
  return cost;
}

bool sameMinimum(const AxisPair& a, const AxisPair& b, double tolerance_deg) {
  return angleBetweenLines(a.axis1, b.axis1) * kRadToDeg <= tolerance_deg &&
         angleBetweenLines(a.axis2, b.axis2) * kRadToDeg <= tolerance_deg;
}

/// Levenberg–Marquardt (Marquardt's diagonal scaling) from `start`, until the
/// Gauss–Newton model promises less than `tolerance` (relative) of the cost.
/// With `known`, it stops as soon as both axes are within kJoinDeg of a
/// minimum found before (that start ends there: the basins are much wider
/// than kJoinDeg), and it gives up (*abandoned) where the cost stays above
/// `abandon_above` while falling by less than kCrawl per step (Gauss–Newton
/// crawls through regions of large residual; no rival minimum lies there).
HingeMinimum descend(const std::vector<RateSample>& samples, std::size_t stride, const AxisPair& start,
                     int iterations, double tolerance, const std::vector<HingeMinimum>* known,
                     double abandon_above = std::numeric_limits<double>::infinity(), bool* abandoned = nullptr) {
  if (abandoned) *abandoned = false;
  Frame f1(start.axis1), f2(start.axis2);
  Matrix4 H;
  Vector4 g;
  double cost = evaluate(samples, stride, f1, f2, &H, &g);
  double mu = 1e-3;
  for (int it = 0; it < iterations; ++it) {
    bool accepted = false;
    for (int attempt = 0; attempt < 12 && !accepted; ++attempt) {
      Matrix4 A = H;
      const double floor = 1e-12 * std::max(H.diagonal().maxCoeff(), 1e-300);
      for (int i = 0; i < 4; ++i) A(i, i) += mu * std::max(H(i, i), floor);
      const Vector4 step = -A.ldlt().solve(g);
      if (!step.allFinite()) break;
      // The Gauss–Newton model's decrease of Σr² for this step; below the tolerance the descent is done.
      const double predicted = -2.0 * g.dot(step) - step.dot(H * step);
      if (predicted <= tolerance * cost) return {{f1.j, f2.j}, cost};
      const Frame n1(f1.moved(step[0], step[1])), n2(f2.moved(step[2], step[3]));
      Matrix4 Hn;
      Vector4 gn;
      const double trial = evaluate(samples, stride, n1, n2, &Hn, &gn);
      if (trial < cost) {
        const bool settled = cost - trial <= tolerance * cost || step.norm() < 1e-9;
        const bool crawling = trial > abandon_above && cost - trial < kCrawl * cost;
        f1 = n1;
        f2 = n2;
        H = Hn;
        g = gn;
        cost = trial;
        mu = std::max(mu / 3.0, 1e-12);
        accepted = true;
        if (settled) return {{f1.j, f2.j}, cost};
        if (crawling && abandoned) {
          *abandoned = true;
          return {{f1.j, f2.j}, cost};
        }
        if (known)
          for (const HingeMinimum& m : *known)
            if (sameMinimum(m.axes, {f1.j, f2.j}, kJoinDeg)) return m;  // (its start stays the earlier one)
      } else {
        mu *= 4.0;
      }
    }
    if (!accepted) break;
  }
  return {{f1.j, f2.j}, cost};
}

/// Adds m unless a better one is the same minimum (replaces a worse one).
void merge(std::vector<HingeMinimum>* minima, const HingeMinimum& m, double tolerance_deg) {
  for (HingeMinimum& x : *minima)
    if (sameMinimum(x.axes, m.axes, tolerance_deg)) {
      if (m.cost < x.cost) {
        const int start = std::min(x.start, m.start);
        x = m;
        x.start = start;
      }
      return;
    }
  minima->push_back(m);
}

/// The 6 lines through opposite vertices of an icosahedron.
std::vector<Eigen::Vector3d> gridLines() {
  const double phi = 0.5 * (1.0 + std::sqrt(5.0));
  std::vector<Eigen::Vector3d> lines = {{0.0, 1.0, phi}, {0.0, -1.0, phi}, {1.0, phi, 0.0},
                                        {-1.0, phi, 0.0}, {phi, 0.0, 1.0},  {-phi, 0.0, 1.0}};
  for (Eigen::Vector3d& l : lines) l.normalize();
  return lines;
}

std::vector<RateSample> rateSamples(const std::vector<Eigen::Vector3d>& w1, const std::vector<Eigen::Vector3d>& w2) {
  std::vector<RateSample> samples;
  samples.reserve(w1.size());
  for (std::size_t k = 0; k < w1.size(); ++k) {
    const double n1 = w1[k].squaredNorm(), n2 = w2[k].squaredNorm();
    samples.push_back({w1[k], w2[k], n1, n2,
                       GyroHingeResidual::kFloor * GyroHingeResidual::kFloor * (n1 + n2) + 1e-300});
  }
  return samples;
}

}  // namespace

double hingeRateCost(const std::vector<Eigen::Vector3d>& w1, const std::vector<Eigen::Vector3d>& w2,
                     const AxisPair& axes) {
  return evaluate(rateSamples(w1, w2), 1, Frame(axes.axis1), Frame(axes.axis2), nullptr, nullptr);
}

std::vector<HingeMinimum> hingeMinimaFromRates(const std::vector<Eigen::Vector3d>& w1,
                                               const std::vector<Eigen::Vector3d>& w2,
                                               const std::vector<AxisPair>& seeds) {
  const std::vector<RateSample> samples = rateSamples(w1, w2);
  if (samples.empty()) return {};
  const std::size_t stride = (samples.size() + kSearchSamples - 1) / kSearchSamples;

  std::vector<AxisPair> starts = seeds;
  const std::vector<Eigen::Vector3d> lines = gridLines();
  for (const Eigen::Vector3d& a : lines)
    for (const Eigen::Vector3d& b : lines) starts.push_back({a, b});

  std::vector<HingeMinimum> coarse;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < starts.size(); ++i) {
    bool abandoned = false;
    HingeMinimum m = descend(samples, stride, starts[i], kStartIterations, kStartTolerance, &coarse,
                             kAbandonFactor * best, &abandoned);
    if (abandoned) continue;
    if (m.start < 0) m.start = static_cast<int>(i);
    best = std::min(best, m.cost);
    merge(&coarse, m, kSameMinimumDeg);
  }
  const std::size_t used = (samples.size() + stride - 1) / stride;
  const double variance = best / std::max<double>(1.0, static_cast<double>(used) - 4.0);
  std::vector<HingeMinimum> minima;
  for (const HingeMinimum& m : coarse) {
    if (m.cost > best && !(m.cost - best <= kPolishChiSquare * variance)) continue;
    HingeMinimum polished = descend(samples, 1, m.axes, kPolishIterations, kPolishTolerance, nullptr);
    polished.start = m.start;
    merge(&minima, polished, kSameMinimumDeg);
  }
  std::sort(minima.begin(), minima.end(),
            [](const HingeMinimum& a, const HingeMinimum& b) { return a.cost < b.cost; });
  return minima;
}

}  // namespace calibration
}  // namespace lieflow
