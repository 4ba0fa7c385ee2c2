/// \file
/// `lieflow integrators` and `lieflow scenes`: what the command knows.
#include <iomanip>
#include <sstream>
#include <iostream>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "integrators/registry.hpp"
#include "joints/scene.hpp"
#include "joints/simulation.hpp"

namespace lieflow {
namespace app {

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
              << (i.is_adaptive ? "yes" : "no") << std::setw(8) << (i.supports_joints ? "yes" : "no")
              << i.description << "\n";
    const std::string indent(11, ' ');
    std::cout << indent << "with joints: " << i.joints_note
              << (runsInJointCoordinates(i.name) ? "; in joint coordinates where they represent the scene" : "") << "\n";
    for (const IntegratorOption& o : i.options) {
      std::ostringstream line;
      line << indent << "option " << o.name << " = " << o.default_value << " (" << o.meaning << "; "
           << (o.integer ? "integer " : "") << (o.excluded_min ? "> " : "from ") << o.min << " to " << o.max << ")";
      std::cout << line.str() << "\n";
    }
  }
  std::cout << "\nOptions are given as --options KEY=VALUE,... or in the scene's \"integrator\" object.\n"
            << "Scenes with joints run in joint coordinates wherever they represent the scene and the\n"
               "integrator runs there (trees of revolute, universal (offset too), gimbal, prismatic and spherical joints from the\n"
               "ground, from rotation-only bodies or from free roots (those with rkmk*, cg3 and cf4);\n"
               "joints closing loops and gear rows on multipliers,\n"
               "with the explicit integrators), else in maximal coordinates (bodies' poses with\n"
               "multipliers); --formulation maximal|joint chooses, and --stats prints the one used.\n";
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
