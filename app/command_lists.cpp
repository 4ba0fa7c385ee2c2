/// \file
/// `lieflow integrators` and `lieflow scenes`: what the command knows.
#include <iomanip>
#include <sstream>
#include <iostream>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/flag_spelling.hpp"
#include "integrators/registry.hpp"
#include "model/scene.hpp"
#include "simulation/stepper_table.hpp"

namespace lieflow {
namespace app {

namespace {

/// The joint-coordinate columns of the table of steppers where the
/// integrator has a stepper, or why it has none in any.
std::string jointColumns(const std::string& integrator) {
  std::string held, why;
  for (const auto& column : {std::make_pair(SystemKind::kJointTree, "trees"),
                             std::make_pair(SystemKind::kJointCoupled, "coupling rows"),
                             std::make_pair(SystemKind::kJointLoops, "closed loops and gear rows")}) {
    const std::string none = stepperUnavailable(integrator, column.first);
    if (none.empty()) {
      held += std::string(held.empty() ? " " : ", ") + column.second;
      if (!notDefaultReason(integrator, column.first).empty()) held += " (when asked for: --formulation joint)";
    } else if (why.empty()) {
      why = none;
    }
  }
  if (held.empty()) return " no (" + why + ")";
  return held + (why.empty() ? "" : " (not: " + why + ")");
}

}  // namespace

int runIntegrators(int argc, char** argv) {
  const Arguments args(argc, argv, {}, {});
  if (args.help()) {
    std::cout << "usage: lieflow integrators\n\nLists the integrators with their order, properties, whether they\n"
                 "run scenes with joints, and their options (default and admitted range).\n";
    return kSuccess;
  }
  if (!args.positional().empty()) throw UsageError("integrators takes no arguments");
  std::cout << std::left << std::setw(11) << "name" << std::setw(7) << "order" << std::setw(10) << "implicit"
            << std::setw(12) << "symplectic" << std::setw(10) << "momentum" << std::setw(10) << "adaptive"
            << std::setw(8) << "joints" << "description\n";
  for (const IntegratorInfo& i : integratorRegistry()) {
    std::cout << std::setw(11) << i.name << std::setw(7) << (i.order == 0 ? "exact" : std::to_string(i.order))
              << std::setw(10) << (i.is_implicit ? "yes" : "no") << std::setw(12) << (i.is_symplectic ? "yes" : "no")
              << std::setw(10) << (i.preserves_momentum ? "yes" : "no") << std::setw(10)
              << (i.is_adaptive ? "yes" : "no") << std::setw(8) << (stepperUnavailable(i.name, SystemKind::kMaximal).empty() ? "yes" : "no")
              << i.description << "\n";
    const std::string indent(11, ' ');
    const std::string maximal = stepperUnavailable(i.name, SystemKind::kMaximal);
    std::cout << indent << "with joints: " << spellFlags(maximal.empty() ? i.joints_note : "no: " + maximal) << "\n";
    std::cout << indent << "in joint coordinates:" << spellFlags(jointColumns(i.name)) << "\n";
    for (const IntegratorOption& o : i.options) {
      std::ostringstream line;
      line << indent << "option " << o.name << " = " << o.default_value << " (" << o.meaning << "; "
           << (o.integer ? "integer " : "") << (o.excluded_min ? "> " : "from ") << o.min << " to " << o.max << ")";
      std::cout << line.str() << "\n";
    }
  }
  std::cout << "\nOptions are given as --options KEY=VALUE,... or in the scene's \"integrator\" object.\n"
            << "Scenes with joints run in joint coordinates wherever they represent the scene (trees of\n"
               "revolute, universal (offset too), gimbal, prismatic and spherical joints from the ground, from\n"
               "rotation-only bodies or from free roots; couplings, loop-closing joints and gear rows on\n"
               "multipliers) and the integrator has a stepper there (the lines above), else in maximal\n"
               "coordinates (bodies' poses with multipliers); --formulation maximal|joint chooses, and --stats\n"
               "prints the one used.\n";
  return kSuccess;
}

int runScenes(int argc, char** argv) {
  const Arguments args(argc, argv, {}, {});
  if (args.help()) {
    std::cout << "usage: lieflow scenes\n\nLists the built-in scenes (their JSON is in scenes/).\n";
    return kSuccess;
  }
  if (!args.positional().empty()) throw UsageError("scenes takes no arguments");
  for (const BuiltinScene& s : builtinScenes()) {
    const SceneDescription scene = parseScene(s.json, "built-in scene '" + s.name + "'");
    std::cout << std::left << std::setw(20) << s.name << scene.description << "\n";
  }
  std::cout << std::left << std::setw(20) << "chain-N"
            << "N rods of 0.5 m on revolute joints (axes alternate y, z), released horizontal under gravity "
               "(N = 1 ... 100000, e.g. chain-100)\n";
  return kSuccess;
}

}  // namespace app
}  // namespace lieflow
