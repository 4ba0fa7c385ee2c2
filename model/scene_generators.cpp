/// \file
/// Built-in scenes generated from their name: `chain-N`, N rods on revolute
/// joints (the chain-scaling scene of the joints issue).
#include <cmath>
#include <sstream>
#include <string>

#include "model/scene.hpp"

namespace lieflow {

namespace {

/// chain-N: rod i (0.5 m along its body x, m = 0.5 kg, I = diag(1e-4,
/// m L²/12, m L²/12)) has its centre of mass at ((i + ½) 0.5, 0, 0), all rods
/// start horizontal and at rest; joint i hinges rod i to rod i−1 (rod 0 to
/// the ground at the origin) about y for even i and z for odd i, so the chain
/// falls in 3-D under gravity.
std::string chainJson(long n) {
  std::ostringstream s;
  s.precision(17);
  const double L = 0.5, m = 0.5, It = m * L * L / 12.0;
  s << "{\"name\": \"chain-" << n << "\",\n"
    << "\"description\": \"" << n
    << " rods of 0.5 m on revolute joints (axes alternate y, z), released horizontal under gravity\",\n"
    << "\"gravity\": [0, 0, -9.81],\n\"bodies\": [\n";
  for (long i = 0; i < n; ++i)
    s << (i ? ",\n" : "") << "{\"name\": \"rod" << i << "\", \"mass\": " << m << ", \"inertia\": [0.0001, " << It
      << ", " << It << "], \"position\": [" << (i + 0.5) * L << ", 0, 0]}";
  s << "],\n\"joints\": [\n";
  for (long i = 0; i < n; ++i)
    s << (i ? ",\n" : "") << "{\"name\": \"hinge" << i << "\", \"type\": \"revolute\", \"main\": \""
      << (i == 0 ? std::string("ground") : "rod" + std::to_string(i - 1)) << "\", \"secondary\": \"rod" << i
      << "\", \"anchor_main\": [" << (i == 0 ? 0.0 : L / 2) << ", 0, 0], \"anchor_secondary\": [" << -L / 2
      << ", 0, 0], \"axis_main\": " << (i % 2 ? "[0, 0, 1]" : "[0, 1, 0]") << "}";
  s << "],\n\"integrator\": {\"name\": \"rkmk4\", \"dt\": 0.0005},\n\"t_end\": 0.5}\n";
  return s.str();
}

}  // namespace

bool generatedScene(const std::string& name, std::string* json) {
  const std::string prefix = "chain-";
  if (name.compare(0, prefix.size(), prefix) != 0) return false;
  const std::string digits = name.substr(prefix.size());
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos)
    return false;
  const long n = std::stol(digits);
  if (n < 1) return false;
  *json = chainJson(n);
  return true;
}

}  // namespace lieflow
