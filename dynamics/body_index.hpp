/// \file
/// The body index both formulations of dynamics/ and their kernels give the
/// ground: a joint's, a gear's or a row group's body slot that is no body.
#pragma once

namespace lieflow {

/// The body index of the ground.
constexpr int kGround = -1;

}  // namespace lieflow
