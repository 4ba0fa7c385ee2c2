/// \file
/// The resource limits of lieflow, in one place: how large an input file may
/// be, how many rows a recording, how many bodies a scene, how many steps a run
/// and how many integration substeps a fit may take. Each guards against an
/// input that would otherwise exhaust memory or run without end (an endless
/// stream such as /dev/zero, a step that rounds the step count to 10¹⁶, a
/// recording whose time column is in milliseconds). A limit that is hit is an
/// error naming the limit, the value asked for and the option that raises it
/// (`limitExceeded`); every limit can be raised, none is silent.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

#include "liegroup/invalid_input.hpp"

namespace lieflow {

/// Largest scene or recording file read [bytes] (1 GiB; a 10⁶-row recording
/// of two bodies' quaternions and rates is about 0.3 GB). Raised by
/// `--max-input-mb`.
constexpr std::uint64_t kMaxInputBytes = std::uint64_t{1} << 30;

/// Most data rows of a recording (10⁷). Raised by `--max-rows`.
constexpr long kMaxRecordingRows = 10000000;

/// Most bodies of a scene (10⁵; `chain-N` is generated up to this). Raised by
/// `--max-bodies`.
constexpr long kMaxBodies = 100000;

/// Most bodies an MJCF model's files may declare before MuJoCo compiles them
/// (10⁴), unless --max-bodies is given: MuJoCo 2.2's compiler takes time
/// quadratic in the bodies (3 s at 10⁴ bodies, 19 s at 3·10⁴ on a 2-core
/// machine) and beyond about 2.5·10⁴ runs out of its default stack after
/// that time. Raised by `--max-bodies`.
constexpr long kMaxMjcfBodies = 10000;

/// Most steps (accepted plus rejected) of one run (10⁸: 20 s of a free body,
/// several minutes of a jointed scene). Raised by `--max-steps`.
constexpr long kMaxSteps = 100000000;

/// Most integration substeps of one shooting pass of a spring fit (10⁷).
/// Raised by `--max-substeps`.
constexpr long kMaxSubsteps = 10000000;

/// The limits in force for one command (the defaults above unless raised).
struct ResourceLimits {
  std::uint64_t max_input_bytes = kMaxInputBytes;
  long max_rows = kMaxRecordingRows;
  long max_bodies = kMaxBodies;
  long max_mjcf_bodies = kMaxMjcfBodies;
  long max_steps = kMaxSteps;
  long max_substeps = kMaxSubsteps;
};

/// The error of a limit that was hit: "FIELD: needs N STEPS, above the limit
/// of M (raise it with OPTION)". `field` names the input that asked for it.
inline InvalidInput limitExceeded(const std::string& field, const std::string& what, double needed,
                                  double limit, const std::string& option) {
  auto count = [](double v) {
    if (!(v < 1e300)) return std::string("more than 1e300");  // a step of 1e-320 over a second
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, v < 1e15 ? "%.0f" : "%.3g", v);
    return std::string(buffer);
  };
  return InvalidInput(field, "needs " + count(needed) + " " + what + ", above the limit of " + count(limit) +
                                 " (raise it with " + option + ")");
}

}  // namespace lieflow
