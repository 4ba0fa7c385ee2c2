/// \file
/// Bad scene input is rejected with a message naming the source, the field
/// and the reason; good input reads back exactly.
#include <gtest/gtest.h>

#include <string>

#include "model/scene.hpp"
#include "simulation/simulation.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace {

const char* kGood = R"({
  "name": "t", "gravity": [0, 0, -9.81],
  "bodies": [{"name": "b", "mass": 2, "inertia": [1, 2, 2.5],
              "orientation": [1, 0, 0, 0], "angular_velocity": [1, 2, 3]}],
  "integrator": {"name": "rkmk4", "dt": 0.01}, "t_end": 1
})";

/// Replaces the first occurrence of `from` in kGood by `to`.
std::string variant(const std::string& from, const std::string& to) {
  std::string s = kGood;
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return s.replace(pos, from.size(), to);
}

/// Expects InvalidInput whose message contains every fragment.
void expectRejected(const std::string& json, std::initializer_list<const char*> fragments) {
  try {
    Simulation sim(parseScene(json, "scene.json"));
    FAIL() << "accepted: " << json;
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("scene.json"), std::string::npos) << what;
    for (const char* f : fragments) EXPECT_NE(what.find(f), std::string::npos) << "'" << f << "' not in: " << what;
  }
}

TEST(SceneInput, GoodSceneReads) {
  const SceneDescription s = parseScene(kGood, "scene.json");
  EXPECT_EQ(s.name, "t");
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0].inertia(2, 2), 2.5);
  EXPECT_EQ(s.integrator.name, "rkmk4");
  EXPECT_EQ(s.t_end, 1.0);
  EXPECT_EQ(Simulation(s).columns().size(), 1u + 7 + 6 + 5);
}

TEST(SceneInput, MissingFields) {
  expectRejected(variant(R"("mass": 2, )", ""), {"bodies[0].mass", "missing"});
  expectRejected(variant(R"("name": "t", )", ""), {"name", "missing"});
  expectRejected(variant(R"("inertia": [1, 2, 2.5],)", ""), {"bodies[0].inertia", "missing"});
}

TEST(SceneInput, UnknownFieldsAndWrongTypes) {
  expectRejected(variant(R"("mass": 2)", R"("mass": 2, "colour": "red")"), {"bodies[0].colour", "unknown field"});
  expectRejected(variant(R"("mass": 2)", R"("mass": "2")"), {"bodies[0].mass", "expected a number"});
  expectRejected(variant(R"("t_end": 1)", R"("t_end": 1, "tend": 2)"), {"tend", "unknown field"});
  expectRejected(variant(R"([1, 2, 3]})", R"([1, 2]})"), {"angular_velocity", "expected 3 numbers"});
  expectRejected("{ not json", {"not valid JSON"});
}

TEST(SceneInput, NonFiniteAndNonPhysical) {
  // JSON has no NaN/Inf literal; an overflowing number is rejected by the parser.
  expectRejected(variant(R"("mass": 2)", R"("mass": 1e999)"), {"not valid JSON", "1e999"});
  expectRejected(variant(R"("mass": 2)", R"("mass": -1)"), {"bodies[0].mass", "positive"});
  expectRejected(variant("[1, 2, 2.5]", "[1, -2, 2.5]"), {"bodies[0].inertia", "positive definite"});
  expectRejected(variant("[1, 2, 2.5]", "[1, 1, 3]"), {"bodies[0].inertia", "triangle inequality"});
  expectRejected(variant("[1, 2, 2.5]", "[[1, 0.5, 0], [0, 2, 0], [0, 0, 2.5]]"),
                 {"bodies[0].inertia", "not symmetric"});
  expectRejected(variant("[1, 0, 0, 0]", "[0, 0, 0, 0]"), {"bodies[0].orientation", "norm"});
  expectRejected(variant("[1, 0, 0, 0]", "[2, 0, 0, 0]"), {"bodies[0].orientation", "norm"});
  expectRejected(variant(R"("dt": 0.01)", R"("dt": 0)"), {"integrator.dt", "positive"});
}

TEST(SceneInput, NearUnitQuaternionIsNormalized) {
  const SceneDescription s = parseScene(variant("[1, 0, 0, 0]", "[1.0000001, 0, 0, 0]"), "scene.json");
  EXPECT_NEAR(s.bodies[0].orientation.norm(), 1.0, 1e-15);
}

TEST(SceneInput, JointsNameBodiesThatExist) {
  const std::string with_joint = variant(
      R"("integrator")",
      R"("joints": [{"name": "p", "type": "spherical", "main": "ground", "secondary": "nobody",
                     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, -1]}], "integrator")");
  expectRejected(with_joint, {"joints[0].secondary", "unknown body 'nobody'"});
  expectRejected(variant(R"("integrator")", R"("joints": [{"name": "p", "type": "hinge"}], "integrator")"),
                 {"joints[0].type", "unknown joint type"});
  expectRejected(
      variant(R"("integrator")",
              R"("joints": [{"name": "p", "type": "spherical", "main": "b", "secondary": "b",
                             "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0]}], "integrator")"),
      {"joints[0].secondary", "itself"});
}

TEST(SceneInput, PositionInconsistentWithPivotIsRejected) {
  const std::string s = variant(
      R"("orientation")",
      R"("position": [0, 0, 5], "orientation")");
  const std::string with_joint = std::string(s).replace(
      s.find(R"("integrator")"), 12,
      R"("joints": [{"name": "p", "type": "spherical", "main": "ground", "secondary": "b",
                    "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, -1]}], "integrator")");
  expectRejected(with_joint, {"bodies[0].position", "inconsistent with joint 'p'"});
}

TEST(SceneInput, UnknownSceneNameListsBuiltins) {
  try {
    loadScene("no-such-scene");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("heavy-top"), std::string::npos) << e.what();
  }
}

TEST(SceneInput, EveryBuiltinSceneLoadsAndAssembles) {
  for (const BuiltinScene& b : builtinScenes()) {
    const Simulation sim(loadScene(b.name));
    EXPECT_FALSE(sim.scene().description.empty()) << b.name;
    EXPECT_TRUE(sim.scene().has_integrator && sim.scene().has_t_end) << b.name;
  }
}

}  // namespace
}  // namespace lieflow
