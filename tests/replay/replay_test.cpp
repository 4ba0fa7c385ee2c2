// The replay (replay/): frames kept within their budget, the run's CSV read
// strictly, a body's inertia box that has its inertia, model files' shapes
// placed where the model puts them, and the command's errors and exit codes.
// The page in a real browser: tests/app/replay_browser_test.py.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include <Eigen/Eigenvalues>

#include "model/import/model_import.hpp"
#include "model/scene.hpp"
#include "liegroup/invalid_input.hpp"
#include "replay/replay_page.hpp"
#include "replay/replay_scene.hpp"
#include "replay/run_table.hpp"
#include "tests/command_runner.hpp"

namespace lieflow {
namespace {

using replay::FrameDecimator;
using testing_support::runLieflow;

std::string model(const std::string& file) { return std::string(LIEFLOW_SOURCE_DIR) + "/tests/data/models/" + file; }

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = std::string(LIEFLOW_BINARY_DIR) + "/replay-test-" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(ReplayFrames, KeepFirstLastAndAUniformStrideWithinTheBudgetAndNeverHoldMore) {
  for (const std::size_t budget : {2u, 3u, 10u, 2000u}) {
    for (const std::size_t n : {1u, 2u, 5u, 11u, 1999u, 2000u, 2001u, 4000u, 100000u, 1234567u}) {
      FrameDecimator d(budget);
      for (std::size_t i = 0; i < n; ++i) d.offer({double(i)});
      const auto frames = d.frames();
      ASSERT_LE(frames.size(), budget) << budget << " " << n;
      ASSERT_EQ(frames.front()[0], 0.0);
      ASSERT_EQ(frames.back()[0], double(n - 1));
      // Every frame but the last is a multiple of the stride, consecutive.
      for (std::size_t k = 0; k + 1 < frames.size(); ++k) ASSERT_EQ(frames[k][0], double(k * d.stride()));
      // Not thinner than needed: the next smaller stride would not fit.
      if (n > budget) EXPECT_GE(frames.size(), budget / 4) << budget << " " << n;
      if (n <= budget) EXPECT_EQ(frames.size(), n);
    }
  }
}

TEST(ReplayRunTable, NamesTheLineAndColumnOfABadValueAndRefusesARunThatGoesBack) {
  const std::string good = writeFile("good.csv", "t,a.qw,a.qx,a.qy,a.qz,energy\n0,1,0,0,0,2\n0.5,1,0,0,0,3\n");
  const replay::RunTable t = replay::readRunTable(good, 100, ResourceLimits());
  EXPECT_EQ(t.total_rows, 2u);
  EXPECT_EQ(t.column("energy"), 5);
  const struct {
    const char* text;
    const char* field;
  } bad[] = {{"t,a\n0,1\n0.1,nan\n", "line 3, column a"},
             {"t,a\n0,1\n0.1,1e999\n", "line 3, column a"},
             {"t,a\n0,1\n0.1\n", "line 3"},
             {"t,a\n0,1\n0.1,2x\n", "line 3, column a"},
             {"t,a\n0,1\n0,2\n", "line 3, column t"},
             {"a,t\n1,0\n", "line 1, column 1"},
             {"t,a\n", ""},
             {"", ""}};
  for (const auto& b : bad) {
    const std::string path = writeFile("bad.csv", b.text);
    try {
      replay::readRunTable(path, 100, ResourceLimits());
      ADD_FAILURE() << "accepted: " << b.text;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(b.field), std::string::npos) << e.what();
    }
  }
  ResourceLimits few;
  few.max_rows = 1;
  EXPECT_THROW(replay::readRunTable(good, 100, few), InvalidInput);
}

TEST(ReplayInertiaBox, HasTheBodysMassAndPrincipalMomentsAboutItsAxes) {
  BodyDescription b;
  b.mass = 3.0;
  const Eigen::Quaterniond turn = Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized();
  b.inertia = turn * Eigen::Vector3d(0.05, 0.11, 0.13).asDiagonal() * turn.conjugate().toRotationMatrix();
  const VisualShape box = replay::inertiaBox(b);
  // The solid box's inertia, turned back into body axes.
  const Eigen::Vector3d h = box.size;
  const Eigen::Vector3d I_box(b.mass * (h.y() * h.y() + h.z() * h.z()) / 3.0,
                              b.mass * (h.x() * h.x() + h.z() * h.z()) / 3.0,
                              b.mass * (h.x() * h.x() + h.y() * h.y()) / 3.0);
  const Eigen::Matrix3d R = box.orientation.toRotationMatrix();
  const Eigen::Matrix3d I = R * I_box.asDiagonal() * R.transpose();
  EXPECT_LT((I - b.inertia).norm(), 1e-13 * b.inertia.norm()) << I;
}

TEST(ReplayShapes, UrdfVisualsSitWhereTheLinkPutsThemAndMeshesResolve) {
  const SceneDescription scene = loadScene(model("arm6_shapes.urdf"));
  // link1's box: 0.06 x 0.06 x 0.2 m at (0, 0, 0.1) in the link frame, whose
  // origin is 0.1 m above the world's; the body's centre is at (0, 0.01, 0.2).
  const BodyDescription& link1 = scene.bodies[scene.bodyIndex("link1")];
  ASSERT_EQ(link1.visuals.size(), 1u);
  EXPECT_EQ(link1.visuals[0].kind, VisualShape::Kind::kBox);
  EXPECT_LT((link1.visuals[0].size - Eigen::Vector3d(0.03, 0.03, 0.1)).norm(), 1e-15);
  EXPECT_LT((link1.visuals[0].position - Eigen::Vector3d(0.0, -0.01, 0.0)).norm(), 1e-15);
  // The base (the fixed root) is drawn with the ground.
  ASSERT_EQ(scene.ground_visuals.size(), 1u);
  EXPECT_EQ(scene.ground_visuals[0].kind, VisualShape::Kind::kCylinder);
  // Relative and package:// meshes resolve to the test's STL; a missing one keeps its name.
  const auto& l3 = scene.bodies[scene.bodyIndex("link3")].visuals;
  const auto& l4 = scene.bodies[scene.bodyIndex("link4")].visuals;
  const auto& l6 = scene.bodies[scene.bodyIndex("link6")].visuals;
  ASSERT_EQ(l3.size(), 1u);
  ASSERT_EQ(l4.size(), 1u);
  ASSERT_EQ(l6.size(), 1u);
  EXPECT_EQ(l3[0].mesh_file, model("meshes/wedge.stl"));
  EXPECT_EQ(l4[0].mesh_file, model("meshes/wedge.stl"));
  EXPECT_EQ(l6[0].mesh_file, "package://missing_description/meshes/link6.dae");
  EXPECT_EQ(l4[0].mesh_scale, Eigen::Vector3d::Constant(0.08));
}

#ifdef LIEFLOW_HAVE_MUJOCO
TEST(ReplayShapes, MjcfGeomsAreMuJoCosVisibleGeomsOfEachBody) {
  const std::string humanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml";
  if (!std::ifstream(humanoid)) GTEST_SKIP() << "MuJoCo's sample models are not installed";
  ModelImportOptions options;
  options.ignore = {"contacts", "limits", "armature", "actuators", "tendons", "equalities", "friction", "fluid"};
  const SceneDescription scene = importModel(humanoid, options);
  std::size_t shapes = 0;
  for (const BodyDescription& b : scene.bodies) {
    shapes += b.visuals.size();
    // Every shape lies within its body's reach (a humanoid's limb: under 0.5 m).
    for (const VisualShape& s : b.visuals) EXPECT_LT(s.position.norm(), 0.5) << b.name << " " << s.origin;
  }
  // humanoid.xml: 19 geoms on its 13 bodies, the floor on the world (a plane: not drawn).
  EXPECT_EQ(shapes, 19u);
  EXPECT_TRUE(scene.ground_visuals.empty());
}
#endif

TEST(ReplayCommand, WritesAPageThatHoldsTheRunAndRefusesARunOfAnotherScene) {
  const std::string dir = std::string(LIEFLOW_BINARY_DIR);
  const std::string run = dir + "/replay-test-run.csv", page = dir + "/replay-test-run.html";
  std::remove(page.c_str());
  ASSERT_EQ(runLieflow("simulate double-pendulum --t-end 0.5 --quiet --out " + run).status, 0);
  const auto o = runLieflow("view " + run + " --scene double-pendulum --frames 50");
  if (o.status == 1 && o.err.find("libjs-three") != std::string::npos) GTEST_SKIP() << o.err;
  ASSERT_EQ(o.status, 0) << o.err;
  std::smatch frames;
  ASSERT_TRUE(std::regex_search(o.err, frames, std::regex("(\\d+) frames of 501 rows"))) << o.err;
  EXPECT_LE(std::stoi(frames[1]), 50);
  EXPECT_GE(std::stoi(frames[1]), 50 / 4);  // a uniform stride: at least a quarter of the budget
  std::stringstream text;
  text << std::ifstream(page).rdbuf();
  const std::string html = text.str();
  EXPECT_NE(html.find("<script id=\"lieflow-run\" type=\"application/json\">"), std::string::npos);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos) << "the page must not load anything";
  EXPECT_EQ(html.find("<script src="), std::string::npos);
  // A run of another scene: exit 2 naming the file and the column.
  const auto other = runLieflow("view " + run + " --scene heavy-top --out " + dir + "/replay-test-other.html");
  EXPECT_EQ(other.status, 2);
  EXPECT_NE(other.err.find(run + ": column top.qw"), std::string::npos) << other.err;
  // Usage errors.
  EXPECT_EQ(runLieflow("view " + run).status, 2);
  EXPECT_EQ(runLieflow("view " + run + " --scene double-pendulum --frames 1").status, 2);
  EXPECT_EQ(runLieflow("view /nonexistent.csv --scene double-pendulum").status, 2);
  // three.js missing: exit 1 saying what to install, and no page left behind.
  ::setenv("LIEFLOW_THREE_DIR", "/nonexistent", 1);
  const auto missing = runLieflow("view " + run + " --scene double-pendulum --out " + dir + "/replay-test-none.html");
  ::unsetenv("LIEFLOW_THREE_DIR");
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.err.find("libjs-three"), std::string::npos) << missing.err;
  EXPECT_FALSE(std::ifstream(dir + "/replay-test-none.html").good());
}

TEST(ReplayCommand, StudyViewReplaysTheReferenceRunBesideThePlots) {
  const std::string dir = std::string(LIEFLOW_BINARY_DIR) + "/replay-test-study";
  const auto o = runLieflow("study heavy-top --integrators rkmk4 --dt 0.01 --t-end 0.5 --min-time 0.001 --no-plots "
                            "--view --out " + dir);
  if (o.status == 1 && o.err.find("libjs-three") != std::string::npos) GTEST_SKIP() << o.err;
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_NE(o.out.find("replay: " + dir + "/replay.html (the reference run, 1001 frames)"), std::string::npos) << o.out;
  std::stringstream text;
  text << std::ifstream(dir + "/replay.html").rdbuf();
  EXPECT_NE(text.str().find("the study's reference (converged rkmk45"), std::string::npos);
}

}  // namespace
}  // namespace lieflow
