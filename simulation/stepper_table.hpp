/// \file
/// The table of steppers, as the command and its messages read it: for each
/// integrator of integrators/registry.hpp (name, order, options), which
/// stepper it builds on each kind of system, or why it builds none. The rows
/// and their factories are in simulation/stepper_table_rows.hpp (internal, the
/// steppers' templates); this header answers the questions `supports`, the
/// error lists and `lieflow integrators` ask, without them.
#pragma once

#include <string>
#include <vector>

namespace lieflow {

/// The kinds of system a scene is assembled into, each with its own column
/// of the table (the stepper differs: a joint's rows are projected, imposed
/// as multipliers, or not there at all).
enum class SystemKind {
  kSingleBody,    ///< one body, free or about a pivot (RotorSystem, FreeBodySystem)
  kMaximal,       ///< bodies' poses with multipliers for the joints (MultibodySystem)
  kJointTree,     ///< a tree in joint coordinates (ArticulatedSystem, no closures)
  kJointCoupled,  ///< a tree whose closures are all coupling rows (constant G)
  kJointLoops,    ///< a tree with loop-closing joints or gear rows
};

/// All kinds, in table order.
inline constexpr SystemKind kSystemKinds[] = {SystemKind::kSingleBody, SystemKind::kMaximal, SystemKind::kJointTree,
                                              SystemKind::kJointCoupled, SystemKind::kJointLoops};

/// The kind as messages name it after "is not available" ("for scenes with
/// joints", "in joint coordinates", ...).
const char* systemKindName(SystemKind kind);

/// Empty if the integrator named builds a stepper for `kind`, else why not.
/// Precondition: the name is in integrators/registry.hpp.
std::string stepperUnavailable(const std::string& integrator, SystemKind kind);

/// The integrators that build a stepper for `kind`, in registry order (the
/// "available:" lists of the error messages).
std::vector<std::string> steppersFor(SystemKind kind);

/// Empty if the integrator's stepper for `kind` may be the default
/// formulation's, else why it runs there only when asked for
/// (`--formulation joint`): a cell whose row says `notDefault(K)`.
std::string notDefaultReason(const std::string& integrator, SystemKind kind);

}  // namespace lieflow
