/// \file
/// A global search for the local minima of the gyroscope hinge cost
/// Σ r², r = GyroHingeResidual (Sampson form, unweighted), over both axes.
///
/// The closed-form starts of hinge_initial.hpp sit in the basin of the global
/// minimum when the motion is rich, but short recordings (≲ 2 s of the
/// `hinge-pair` scene at 100 Hz, ≲ 1 s of the synthetic motions) have two or
/// three basins, and the closed form can land in the wrong one (seen: a
/// minimum 13° off with an RMS residual of three times the noise, reported as
/// converged; on 0.5 s of synthetic motion, minima 50–74° off). Mapped with
/// 196 starts per recording, every basin of those recordings drew at least
/// 10 % of a uniform grid of axis pairs. So the search runs a cheap
/// Levenberg–Marquardt (analytic derivatives, 4×4 normal equations, no Ceres)
/// from
///
///  - the closed-form candidates (`seeds`), and
///  - every pair of the 6 lines through opposite vertices of an icosahedron
///    (the best-spread 6 lines: no line is more than 37° from one of them),
///    36 pairs;
///
/// on at most kSearchSamples samples (every ⌈N/kSearchSamples⌉-th: the
/// basins are those of the motion, not of the sample count). A start that
/// comes within 2° of a minimum found before ends there; one that crawls
/// (Gauss–Newton in a region of large residual) at ten times the best cost
/// so far is abandoned. The distinct end points within a generous Δχ² of the
/// best are polished on all samples and merged (kSameMinimumDeg). The minima
/// come back best first; the refinement (two_axis_solver.hpp) restarts from
/// the best and from those that could rival it, and a second minimum that
/// fits as well as the best makes the fit not identifiable.
///
/// Cost: about 0.4 ms for 1000 samples (≈ 600 subsample evaluations of 100
/// samples, a polish of 1000), 0.3–0.8 ms for 50–200 samples.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"

namespace lieflow {
namespace calibration {

/// Samples the search's starts run on, at most.
constexpr int kSearchSamples = 100;
/// Grid starts: pairs of the 6 icosahedral lines.
constexpr int kGridStarts = 36;
/// Endpoints whose axes both lie within this angle are one minimum (deg).
constexpr double kSameMinimumDeg = 0.5;

/// A local minimum of the unweighted Sampson cost on all samples.
struct HingeMinimum {
  AxisPair axes;
  double cost = 0.0;  ///< Σ r² (rad²/s²)
  int start = -1;     ///< the first start that reached it: seeds[start], or grid pair start − seeds.size()
};

/// The distinct local minima reached from `seeds` and the grid, best first.
std::vector<HingeMinimum> hingeMinimaFromRates(const std::vector<Eigen::Vector3d>& w1,
                                               const std::vector<Eigen::Vector3d>& w2,
                                               const std::vector<AxisPair>& seeds);

/// The unweighted Sampson cost Σ r² of `axes` on all samples.
double hingeRateCost(const std::vector<Eigen::Vector3d>& w1, const std::vector<Eigen::Vector3d>& w2,
                     const AxisPair& axes);

}  // namespace calibration
}  // namespace lieflow
